#pragma once

// ReusableLazyPrmStar: OMPL's LazyPRM* (Bohlin & Kavraki 2000; the k* connection of Karaman &
// Frazzoli 2011) as the low-level planner keeps it between queries (thesis 2.5.3, Algorithm
// 3): one roadmap for the robot's whole mission, its cached validity forgotten only where the
// map changed, milestones the caller checked (guided sampling), one-to-many distances for the
// high-level planner, and a solve() whose time limit holds.
//
// LazyPRM's own solve() repairs a path it found (A* over the roadmap, check the path, delete
// the first invalid edge, A* again) in a loop that does not look at the termination
// condition: on a large roadmap whose edges a new map made unknown, one query ran up to
// 17.8 s against a 1 s limit (powerplant trio, docs/low_level_planner.md). solve() here is
// LazyPRM's with the condition checked before each search of that loop as well.
//
// Included by motion_planner.cpp and its tests only: OMPL's headers stay out of the planner's
// public interface.

#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/geometric/planners/prm/LazyPRMstar.h>

#include <Eigen/Core>
#include <boost/range/iterator_range.hpp>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace scancrew::motion {

class ReusableLazyPrmStar : public ompl::geometric::LazyPRMstar {
 public:
  using State = ompl::base::State;
  using PlannerTerminationCondition = ompl::base::PlannerTerminationCondition;

  explicit ReusableLazyPrmStar(const ompl::base::SpaceInformationPtr& si)
      : ompl::geometric::LazyPRMstar(si) {}
  // Frees the roadmap's states: OMPL 1.5's ~LazyPRM() does not (only clear() does), which
  // LeakSanitizer reported as states allocated in LazyPRM* queries and never freed.
  ~ReusableLazyPrmStar() override;
  ReusableLazyPrmStar(const ReusableLazyPrmStar&) = delete;
  ReusableLazyPrmStar& operator=(const ReusableLazyPrmStar&) = delete;

  size_t vertex_count() const { return boost::num_vertices(g_); }
  size_t edge_count() const { return boost::num_edges(g_); }
  // Adds a milestone the caller has checked (guided sampling); edges unchecked, as LazyPRM*'s
  // own. Needs setup().
  void add_checked_milestone(const State* s);

  // --- solve ---

  // What the last solve() did.
  struct SolveStats {
    size_t searches = 0;  // A* searches over the roadmap, each followed by the path's checks
    // the condition fired while a path found on the roadmap was being repaired (its searches
    // kept finding invalid vertices or edges): LazyPRM's own solve() would have gone on
    bool cut_in_repair = false;
  };
  // LazyPRM::solve(), the termination condition also checked before each repair search.
  ompl::base::PlannerStatus solve(const PlannerTerminationCondition& ptc) override;
  const SolveStats& last_solve() const { return last_solve_; }

  // --- cached validity ---

  // Marks VALIDITY_UNKNOWN the valid vertices whose state `state_touches` and the valid edges
  // whose motion `motion_touches` (the map changed near them); returns how many of each.
  template <class StateTouches, class MotionTouches>
  std::pair<size_t, size_t> forget_validity(const StateTouches& state_touches,
                                            const MotionTouches& motion_touches) {
    std::pair<size_t, size_t> n{0, 0};
    for (const Vertex v : boost::make_iterator_range(boost::vertices(g_))) {
      unsigned int& flags = vertexValidityProperty_[v];
      if ((flags & VALIDITY_TRUE) != 0 && state_touches(stateProperty_[v])) {
        flags = VALIDITY_UNKNOWN;
        ++n.first;
      }
    }
    for (const Edge e : boost::make_iterator_range(boost::edges(g_))) {
      unsigned int& flags = edgeValidityProperty_[e];
      if ((flags & VALIDITY_TRUE) != 0 && motion_touches(stateProperty_[boost::source(e, g_)],
                                                         stateProperty_[boost::target(e, g_)])) {
        flags = VALIDITY_UNKNOWN;
        ++n.second;
      }
    }
    return n;
  }

  // --- one-to-many distances (MotionPlanner::roadmap_distances) ---

  // Adds LazyPRM*'s own samples (edges unchecked, as in solve()) until the roadmap holds
  // `min_vertices` or `ptc` fires; returns how many. Needs setup().
  size_t grow(size_t min_vertices, const PlannerTerminationCondition& ptc);

  struct DistanceResult {
    std::vector<double> distances_m;
    size_t checked_edges = 0;  // roadmap edges whose motion was checked
    size_t removed_edges = 0;
    size_t removed_vertices = 0;
  };

  // Dijkstra from `from` over the roadmap, the targets as sinks (null: skipped, +inf).
  // Links: from → its k nearest vertices, from → each target (the straight motion), each
  // target's k nearest vertices → it, and the roadmap's edges; k as LazyPRM*'s (k*).
  // Lengths: `position` distance. A link is checked only when it is about to settle its
  // head (lazy); a roadmap vertex is checked when it is settled. Valid roadmap edges and
  // vertices are marked VALIDITY_TRUE; invalid ones deleted afterwards, as LazyPRM does.
  // Over 80 lines: one lazy Dijkstra whose queue, marks and deletions every step shares; in
  // pieces they would travel as a dozen arguments.
  template <class Position>
  // NOLINTNEXTLINE(readability-function-size): one Dijkstra, its state shared by every step
  DistanceResult distances(const State* from, const std::vector<const State*>& targets,
                           const Position& position) {
    const size_t k = connection_count();
    // the nearest vertices first: nearest() briefly adds a query vertex to the graph
    const std::vector<Vertex> from_near = nearest(from, k);
    std::vector<std::vector<Vertex>> target_near(targets.size());
    for (size_t t = 0; t < targets.size(); ++t)
      if (targets[t] != nullptr) target_near[t] = nearest(targets[t], k);

    // number the vertices 0..V-1 (constructSolution does the same); targets are V + t
    std::vector<Vertex> verts;
    verts.reserve(boost::num_vertices(g_));
    for (const Vertex v : boost::make_iterator_range(boost::vertices(g_))) {
      indexProperty_[v] = verts.size();
      verts.push_back(v);
    }
    const size_t n = verts.size();
    std::vector<Eigen::Vector3d> pos;
    pos.reserve(n + targets.size());
    for (const Vertex v : verts) pos.push_back(position(stateProperty_[v]));
    for (const State* t : targets)
      pos.push_back(t != nullptr ? position(t) : Eigen::Vector3d::Zero());
    const Eigen::Vector3d p_from = position(from);
    std::vector<std::vector<uint32_t>> attached(n);  // vertex -> targets linked to it
    for (size_t t = 0; t < targets.size(); ++t)
      for (const Vertex v : target_near[t])
        attached[indexProperty_[v]].push_back(static_cast<uint32_t>(t));

    enum class Link : uint8_t { kFromVertex, kEdge, kFromTarget, kVertexTarget };
    struct Entry {
      double d;
      size_t node;  // < n: a vertex, else a target
      size_t via;   // the vertex the link leaves (kEdge, kVertexTarget)
      Link link;
      Edge edge;  // kEdge
      bool operator>(const Entry& o) const { return d > o.d; }
    };
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    std::vector<uint8_t> done(n + targets.size(), 0);
    DistanceResult r;
    r.distances_m.assign(targets.size(), std::numeric_limits<double>::infinity());
    size_t open = 0;
    for (size_t t = 0; t < targets.size(); ++t) {
      if (targets[t] == nullptr) {
        done[n + t] = 1;
        continue;
      }
      ++open;
      queue.push({(pos[n + t] - p_from).norm(), n + t, 0, Link::kFromTarget, Edge()});
    }
    for (const Vertex v : from_near) {
      const size_t i = indexProperty_[v];
      queue.push({(pos[i] - p_from).norm(), i, 0, Link::kFromVertex, Edge()});
    }

    std::vector<Vertex> bad_vertices;
    std::vector<std::pair<Vertex, Vertex>> bad_edges;
    while (!queue.empty() && open > 0) {
      const Entry e = queue.top();
      queue.pop();
      if (done[e.node] != 0) continue;
      if (e.node >= n) {  // a target: its link's motion decides
        const size_t t = e.node - n;
        const State* tail = e.link == Link::kFromTarget ? from : stateProperty_[verts[e.via]];
        if (!si_->checkMotion(tail, targets[t])) continue;
        done[e.node] = 1;
        r.distances_m[t] = e.d;
        --open;
        continue;
      }
      const Vertex v = verts[e.node];
      const State* state = stateProperty_[v];
      unsigned int& vertex_flags = vertexValidityProperty_[v];
      if ((vertex_flags & VALIDITY_TRUE) == 0) {
        if (!si_->isValid(state)) {
          done[e.node] = 1;  // never settled: deleted below
          bad_vertices.push_back(v);
          continue;
        }
        vertex_flags |= VALIDITY_TRUE;
      }
      if (e.link == Link::kFromVertex) {
        if (!si_->checkMotion(from, state)) continue;
      } else {
        unsigned int& edge_flags = edgeValidityProperty_[e.edge];
        if ((edge_flags & VALIDITY_TRUE) == 0) {
          ++r.checked_edges;
          if (!si_->checkMotion(stateProperty_[verts[e.via]], state)) {
            bad_edges.emplace_back(verts[e.via], v);
            continue;
          }
          edge_flags |= VALIDITY_TRUE;
        }
      }
      done[e.node] = 1;
      for (const Edge out : boost::make_iterator_range(boost::out_edges(v, g_))) {
        const size_t j = indexProperty_[boost::target(out, g_)];
        if (done[j] == 0)
          queue.push({e.d + (pos[j] - pos[e.node]).norm(), j, e.node, Link::kEdge, out});
      }
      for (const uint32_t t : attached[e.node])
        if (done[n + t] == 0)
          queue.push({e.d + (pos[n + t] - pos[e.node]).norm(), n + t, e.node, Link::kVertexTarget,
                      Edge()});
    }

    // delete what was found invalid (edges first: a deleted vertex takes its edges along)
    for (const auto& [a, b] : bad_edges) boost::remove_edge(a, b, g_);
    for (const Vertex v : bad_vertices) {
      nn_->remove(v);
      si_->freeState(stateProperty_[v]);
      boost::clear_vertex(v, g_);
      boost::remove_vertex(v, g_);
    }
    r.removed_edges = bad_edges.size();
    r.removed_vertices = bad_vertices.size();
    if (!bad_edges.empty() || !bad_vertices.empty()) recompute_components();
    return r;
  }

 private:
  // LazyPRM*'s number of neighbours for a new milestone (OMPL's KStarStrategy).
  size_t connection_count() const;
  // The k roadmap vertices nearest to a state not in the roadmap (the nearest-neighbour
  // structure compares vertices, so a query vertex is added for the call).
  std::vector<Vertex> nearest(const State* s, size_t k);
  // The connected components LazyPRM keeps for its start-goal test, computed afresh after
  // deletions (LazyPRM splits them per deletion; a search may delete many).
  void recompute_components();

  SolveStats last_solve_;
};

}  // namespace scancrew::motion
