#include "core/motion/reusable_lazy_prm.hpp"

#include <ompl/base/Goal.h>
#include <ompl/base/OptimizationObjective.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/goals/GoalSampleableRegion.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <unordered_set>

namespace scancrew::motion {

namespace ob = ompl::base;

namespace {
// While optimizing (a path found, the cost threshold not met), a new search waits for this
// many milestones added to the solution's component: OMPL 1.5's
// MIN_ADDED_SEGMENTS_FOR_LAZY_OPTIMIZATION, kept so that solve() plans as LazyPRM's does.
constexpr unsigned kMilestonesBeforeNextSearch = 5;
}  // namespace

ReusableLazyPrmStar::~ReusableLazyPrmStar() {
  freeMemory();
  if (nn_) nn_->clear();  // its vertices are gone
}

void ReusableLazyPrmStar::add_checked_milestone(const State* s) {
  const Vertex v = addMilestone(si_->cloneState(s));
  vertexValidityProperty_[v] = VALIDITY_TRUE;
}

ob::PlannerStatus ReusableLazyPrmStar::solve(const PlannerTerminationCondition& ptc) {
  last_solve_ = {};
  checkValidity();
  auto* goal = dynamic_cast<ob::GoalSampleableRegion*>(pdef_->getGoal().get());
  if (goal == nullptr) return ob::PlannerStatus::UNRECOGNIZED_GOAL_TYPE;
  while (const State* s = pis_.nextStart()) startM_.push_back(addMilestone(si_->cloneState(s)));
  if (startM_.empty()) return ob::PlannerStatus::INVALID_START;
  if (!goal->couldSample()) return ob::PlannerStatus::INVALID_GOAL;
  if (goalM_.empty() || goal->maxSampleCount() > goalM_.size()) {
    const State* s = goalM_.empty() ? pis_.nextGoal(ptc) : pis_.nextGoal();
    if (s != nullptr) goalM_.push_back(addMilestone(si_->cloneState(s)));
    if (goalM_.empty()) return ob::PlannerStatus::INVALID_GOAL;
  }

  bestCost_ = opt_->infiniteCost();
  ob::PathPtr best;
  bool found = false;  // a path was found (best: the cheapest, if any was below infinity)
  bool optimal = false;
  unsigned added_since_search = 0;
  std::pair<size_t, size_t> ends;  // indices into startM_, goalM_
  // freed on every way out: constructSolution() throws when A* misses a connected goal
  const std::unique_ptr<State, std::function<void(State*)>> work(
      si_->allocState(), [this](State* s) { si_->freeState(s); });
  while (!ptc) {
    ++iterations_;
    sampler_->sampleUniform(work.get());
    const Vertex added = addMilestone(si_->cloneState(work.get()));
    const long component = solutionComponent(&ends);
    if (component == -1) continue;
    if (found) {
      // optimizing: search again once the solution's component has grown a little
      if (static_cast<long>(vertexComponentProperty_[added]) != component) continue;
      if (++added_since_search < kMilestonesBeforeNextSearch) continue;
      added_since_search = 0;
    }
    const Vertex start = startM_[ends.first];
    const Vertex goal_vertex = goalM_[ends.second];
    // A*, check the path, delete what is invalid, again, while start and goal stay connected
    ob::PathPtr path;
    size_t searches = 0;
    while (path == nullptr &&
           vertexComponentProperty_[start] == vertexComponentProperty_[goal_vertex]) {
      if (searches > 0 && ptc) {  // the change from LazyPRM::solve()
        last_solve_.cut_in_repair = true;
        break;
      }
      ++searches;
      ++last_solve_.searches;
      path = constructSolution(start, goal_vertex);
    }
    if (path == nullptr) continue;
    found = true;
    const ob::Cost cost = path->cost(opt_);
    if (opt_->isCostBetterThan(cost, bestCost_)) {
      best = path;
      bestCost_ = cost;
    }
    if (opt_->isSatisfied(cost)) {
      optimal = true;
      best = path;
      bestCost_ = cost;
      break;
    }
  }

  if (best == nullptr) return ob::PlannerStatus::TIMEOUT;
  ob::PlannerSolution solution(best);
  solution.setPlannerName(getName());
  solution.setOptimized(opt_, bestCost_, optimal);
  pdef_->addSolutionPath(solution);
  return ob::PlannerStatus::EXACT_SOLUTION;
}

size_t ReusableLazyPrmStar::grow(size_t min_vertices, const PlannerTerminationCondition& ptc) {
  size_t added = 0;
  State* work = si_->allocState();
  while (boost::num_vertices(g_) < min_vertices && !ptc) {
    sampler_->sampleUniform(work);
    addMilestone(si_->cloneState(work));
    ++added;
  }
  si_->freeState(work);
  return added;
}

size_t ReusableLazyPrmStar::connection_count() const {
  const double n = std::max(1.0, static_cast<double>(boost::num_vertices(g_)));
  const double dim = std::max(1u, si_->getStateDimension());
  const double k_prm = std::exp(1.0) * (1.0 + 1.0 / dim);
  return static_cast<size_t>(std::ceil(k_prm * std::log(n)));
}

std::vector<ReusableLazyPrmStar::Vertex> ReusableLazyPrmStar::nearest(const State* s, size_t k) {
  std::vector<Vertex> out;
  if (nn_->size() == 0 || k == 0) return out;
  const Vertex q = boost::add_vertex(g_);
  stateProperty_[q] = si_->cloneState(s);
  nn_->nearestK(q, k, out);
  si_->freeState(stateProperty_[q]);
  boost::remove_vertex(q, g_);
  return out;
}

void ReusableLazyPrmStar::recompute_components() {
  componentSize_.clear();
  std::vector<Vertex> stack;
  std::unordered_set<Vertex> seen;
  for (const Vertex v : boost::make_iterator_range(boost::vertices(g_))) {
    if (!seen.insert(v).second) continue;
    const unsigned long component = componentCount_++;
    unsigned long size = 0;
    stack.push_back(v);
    while (!stack.empty()) {
      const Vertex u = stack.back();
      stack.pop_back();
      vertexComponentProperty_[u] = component;
      ++size;
      for (const Vertex w : boost::make_iterator_range(boost::adjacent_vertices(u, g_)))
        if (seen.insert(w).second) stack.push_back(w);
    }
    componentSize_[component] = size;
  }
}

}  // namespace scancrew::motion
