#include "core/tsga/tsga_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <unordered_set>

namespace scancrew::tsga {

namespace {

Result<IntraPath, std::string> intra_path(const PlanCluster& c, const PlannerOptions& o) {
  const size_t m = c.viewpoints.size();
  IntraPath out;
  if (m <= 2) {
    out.viewpoints = c.viewpoints;
    for (uint32_t i = 0; i < m; ++i) out.indices.push_back(i);
    if (m == 2) out.length_m = (c.viewpoints[1] - c.viewpoints[0]).norm();
    return out;
  }
  // shortest open path = closed tour through a dummy node (index m) with free arcs
  CostMatrix costs(m + 1, 0.0);
  for (size_t a = 0; a < m; ++a)
    for (size_t b = 0; b < m; ++b) costs(a, b) = (c.viewpoints[a] - c.viewpoints[b]).norm();
  SolverOptions so;
  so.max_iterations = o.insertion_iterations;
  so.seed = o.seed;
  auto tour = solve_closed_atsp(costs, so);
  if (!tour) return make_unexpected("cluster " + std::to_string(c.id) + ": " + tour.error());
  const auto& nodes = tour->nodes;
  const auto dummy = static_cast<size_t>(
      std::find(nodes.begin(), nodes.end(), static_cast<int>(m)) - nodes.begin());
  for (size_t i = 1; i <= m; ++i) {
    const auto index = static_cast<uint32_t>(nodes[(dummy + i) % (m + 1)]);
    out.indices.push_back(index);
    out.viewpoints.push_back(c.viewpoints[index]);
  }
  for (size_t i = 1; i < m; ++i) out.length_m += (out.viewpoints[i] - out.viewpoints[i - 1]).norm();
  return out;
}

Result<void, std::string> check(const std::vector<PlanRobot>& robots,
                                const std::vector<PlanCluster>& clusters) {
  std::unordered_set<uint32_t> ids;
  for (const PlanRobot& r : robots) {
    if (!ids.insert(r.id).second)
      return make_unexpected("duplicate robot id " + std::to_string(r.id));
    if (!r.position.allFinite())
      return make_unexpected("robot " + std::to_string(r.id) + ": position not finite");
    if (!(r.lambda_tc_per_m >= 0 && r.lambda_ic_per_m >= 0 && std::isfinite(r.lambda_tc_per_m) &&
          std::isfinite(r.lambda_ic_per_m)))
      return make_unexpected("robot " + std::to_string(r.id) +
                             ": penalty terms must be finite and >= 0");
  }
  ids.clear();
  for (const PlanCluster& c : clusters) {
    const std::string name = "cluster " + std::to_string(c.id);
    if (!ids.insert(c.id).second) return make_unexpected("duplicate " + name);
    if (!(c.gain >= 0 && std::isfinite(c.gain)))
      return make_unexpected(name + ": gain must be finite and >= 0");
    if (c.viewpoints.empty()) return make_unexpected(name + ": no viewpoints");
    for (const Eigen::Vector3d& v : c.viewpoints)
      if (!v.allFinite()) return make_unexpected(name + ": viewpoint not finite");
  }
  return {};
}

// One planning problem: the clusters' intra paths, shared by the robots.
class Allocation {
 public:
  Allocation(const std::vector<PlanRobot>& robots, const std::vector<PlanCluster>& clusters,
             std::vector<IntraPath> paths, const PlannerOptions& options)
      : robots_(robots), clusters_(clusters), paths_(std::move(paths)), options_(options) {}

  // f of the arc into cluster v from a node leaving at `exit`, for robot r.
  double utility(const PlanRobot& r, const Eigen::Vector3d& exit, size_t v) const {
    const Eigen::Vector3d& entry = paths_[v].viewpoints.front();
    const double d_kl = options_.travel_distance ? options_.travel_distance(r.type_bit, exit, entry)
                                                 : (entry - exit).norm();
    // a NaN or infinite travel distance (no path) makes the arc worthless, not the plan bad
    if (!std::isfinite(d_kl)) return 0.0;
    return clusters_[v].gain *
           std::exp(-r.lambda_tc_per_m * d_kl - r.lambda_ic_per_m * paths_[v].length_m);
  }

  // maxATSP over {q_0} ∪ set for robot r: the order (cluster indices) and its utility.
  Result<std::pair<std::vector<size_t>, double>, std::string> solve(const PlanRobot& r,
                                                                    const std::vector<size_t>& set,
                                                                    int iterations) const {
    const size_t n = set.size() + 1;
    CostMatrix u(n, 0.0);
    for (size_t a = 0; a < n; ++a) {
      const Eigen::Vector3d exit = a == 0 ? r.position : paths_[set[a - 1]].viewpoints.back();
      for (size_t b = 1; b < n; ++b)
        if (a != b) u(a, b) = utility(r, exit, set[b - 1]);
    }
    SolverOptions so;
    so.max_iterations = iterations;
    so.seed = options_.seed;
    auto path = solve_max_open_path(u, 0, so);
    if (!path) return make_unexpected(path.error());
    std::vector<size_t> order;
    for (size_t i = 1; i < path->nodes.size(); ++i)
      order.push_back(set[static_cast<size_t>(path->nodes[i]) - 1]);
    return std::make_pair(std::move(order), path->utility);
  }

  // Σ g·exp(−λ_tc·D − λ_ic·d(τ_lm)) over the clusters of `order`, D the way from the robot
  // along the order to each cluster's entry (the hops and the intra paths before it); a hop
  // with no path ends the sum (what lies past it is not reached).
  double arrival_utility(const PlanRobot& r, const std::vector<size_t>& order) const {
    double u = 0, way_m = 0;
    Eigen::Vector3d exit = r.position;
    for (size_t v : order) {
      const IntraPath& path = paths_[v];
      const Eigen::Vector3d& entry = path.viewpoints.front();
      const double d = options_.travel_distance ? options_.travel_distance(r.type_bit, exit, entry)
                                                : (entry - exit).norm();
      if (!std::isfinite(d)) break;
      way_m += d;
      u += clusters_[v].gain *
           std::exp(-r.lambda_tc_per_m * way_m - r.lambda_ic_per_m * path.length_m);
      way_m += path.length_m;
      exit = path.viewpoints.back();
    }
    return u;
  }

  // The insertion gain's measure of robot r's solved order (PlannerOptions::gain).
  double value(const PlanRobot& r, const std::pair<std::vector<size_t>, double>& solved) const {
    return options_.gain == PlannerOptions::Gain::kArc ? solved.second
                                                       : arrival_utility(r, solved.first);
  }

  RobotPlan plan_of(const PlanRobot& r, const std::vector<size_t>& order) const {
    RobotPlan p;
    p.robot_id = r.id;
    Eigen::Vector3d exit = r.position;
    for (size_t v : order) {
      const double f = utility(r, exit, v);
      p.clusters.push_back(clusters_[v].id);
      p.utilities.push_back(f);
      p.utility += f;
      p.viewpoints.insert(p.viewpoints.end(), paths_[v].viewpoints.begin(),
                          paths_[v].viewpoints.end());
      for (uint32_t i : paths_[v].indices) p.viewpoint_refs.push_back({clusters_[v].id, i});
      exit = paths_[v].viewpoints.back();
    }
    return p;
  }

 private:
  const std::vector<PlanRobot>& robots_;
  const std::vector<PlanCluster>& clusters_;
  std::vector<IntraPath> paths_;
  const PlannerOptions& options_;
};

Result<std::vector<IntraPath>, std::string> intra_paths(const std::vector<PlanCluster>& clusters,
                                                        const PlannerOptions& options) {
  std::vector<IntraPath> paths;
  paths.reserve(clusters.size());
  IntraPathCache* cache = options.intra_paths;
  const int iterations = options.insertion_iterations;
  for (const PlanCluster& c : clusters) {
    if (cache != nullptr)
      if (const IntraPath* kept = cache->find(c.viewpoints, iterations, options.seed)) {
        paths.push_back(*kept);
        continue;
      }
    const auto start = std::chrono::steady_clock::now();
    auto p = intra_path(c, options);
    if (!p) return make_unexpected(p.error());
    paths.push_back(std::move(p).value());
    if (cache != nullptr)
      cache->insert(
          c.viewpoints, iterations, options.seed, paths.back(),
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
  }
  return paths;
}

}  // namespace

uint64_t IntraPathCache::key(const std::vector<Eigen::Vector3d>& viewpoints, int iterations,
                             uint64_t seed) {
  // FNV-1a over the coordinates' bits, the budget and the seed
  uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](uint64_t word) {
    for (int b = 0; b < 8; ++b) {
      h ^= (word >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  };
  mix(static_cast<uint64_t>(iterations));
  mix(seed);
  for (const Eigen::Vector3d& v : viewpoints)
    for (int a = 0; a < 3; ++a) {
      uint64_t bits = 0;
      std::memcpy(&bits, &v[a], sizeof bits);
      mix(bits);
    }
  return h;
}

IntraPathCache::Map::iterator IntraPathCache::match(Map& map, uint64_t k,
                                                    const std::vector<Eigen::Vector3d>& viewpoints,
                                                    int iterations, uint64_t seed) {
  auto [it, end] = map.equal_range(k);
  for (; it != end; ++it)
    if (it->second.iterations == iterations && it->second.seed == seed &&
        it->second.viewpoints == viewpoints)
      return it;
  return map.end();
}

const IntraPath* IntraPathCache::find(const std::vector<Eigen::Vector3d>& viewpoints,
                                      int iterations, uint64_t seed) {
  const uint64_t k = key(viewpoints, iterations, seed);
  auto it = match(current_, k, viewpoints, iterations, seed);
  if (it == current_.end()) {
    auto old = match(previous_, k, viewpoints, iterations, seed);
    if (old == previous_.end()) {
      ++stats_.misses;
      return nullptr;
    }
    it = current_.emplace(k, std::move(old->second));
    previous_.erase(old);
  }
  ++stats_.hits;
  return &it->second.path;
}

void IntraPathCache::insert(const std::vector<Eigen::Vector3d>& viewpoints, int iterations,
                            uint64_t seed, IntraPath path, double solve_ms) {
  stats_.solve_ms += solve_ms;
  const uint64_t k = key(viewpoints, iterations, seed);
  if (match(current_, k, viewpoints, iterations, seed) != current_.end()) return;
  current_.emplace(k, Entry{.viewpoints = viewpoints,
                            .iterations = iterations,
                            .seed = seed,
                            .path = std::move(path)});
}

void IntraPathCache::new_generation() {
  previous_ = std::move(current_);
  current_.clear();
}

Result<TeamPlan, std::string> plan_tsga(const std::vector<PlanRobot>& robots,
                                        const std::vector<PlanCluster>& clusters,
                                        const PlannerOptions& options) {
  if (auto ok = check(robots, clusters); !ok) return make_unexpected(ok.error());
  TeamPlan plan;
  for (const PlanRobot& r : robots) plan.robots.push_back({.robot_id = r.id});
  if (robots.empty()) {
    for (const PlanCluster& c : clusters) plan.unassigned.push_back(c.id);
    return plan;
  }
  auto paths = intra_paths(clusters, options);
  if (!paths) return make_unexpected(paths.error());
  const Allocation alloc(robots, clusters, std::move(paths).value(), options);

  // rank: distance to the nearest robot that can reach the cluster, ascending (ties: input
  // order); clusters no robot can reach are left out
  std::vector<std::pair<double, size_t>> ranked;
  for (size_t v = 0; v < clusters.size(); ++v) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const PlanRobot& r : robots)
      if ((clusters[v].robot_types & r.type_bit) != 0)
        nearest = std::min(nearest, (clusters[v].viewpoints.front() - r.position).norm());
    if (std::isinf(nearest))
      plan.unassigned.push_back(clusters[v].id);
    else
      ranked.emplace_back(nearest, v);
  }
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });

  std::vector<std::vector<size_t>> sets(robots.size());
  std::vector<double> p(robots.size(), 0.0);
  for (const auto& [distance, v] : ranked) {
    size_t best = robots.size();
    double best_gain = -std::numeric_limits<double>::infinity(), best_p = 0;
    for (size_t k = 0; k < robots.size(); ++k) {
      if ((clusters[v].robot_types & robots[k].type_bit) == 0) continue;
      std::vector<size_t> extended = sets[k];
      extended.push_back(v);
      auto solved = alloc.solve(robots[k], extended, options.insertion_iterations);
      if (!solved) return make_unexpected(solved.error());
      const double value = alloc.value(robots[k], *solved);
      const double gain = value - p[k];
      if (gain > best_gain) {
        best_gain = gain;
        best = k;
        best_p = value;
      }
    }
    sets[best].push_back(v);
    p[best] = best_p;
  }
  for (size_t k = 0; k < robots.size(); ++k) {
    if (sets[k].empty()) continue;
    auto solved = alloc.solve(robots[k], sets[k], options.final_iterations);
    if (!solved) return make_unexpected(solved.error());
    plan.robots[k] = alloc.plan_of(robots[k], solved->first);
  }
  return plan;
}

Result<RobotPlan, std::string> plan_dist_tsga(uint32_t self, const std::vector<PlanRobot>& robots,
                                              const std::vector<PlanCluster>& clusters,
                                              const PlannerOptions& options) {
  const auto it =
      std::find_if(robots.begin(), robots.end(), [&](const PlanRobot& r) { return r.id == self; });
  if (it == robots.end())
    return make_unexpected("robot " + std::to_string(self) + " is not in the team");
  auto team = plan_tsga(robots, clusters, options);
  if (!team) return make_unexpected(team.error());
  return team->robots[static_cast<size_t>(it - robots.begin())];
}

Result<RobotPlan, std::string> plan_for_idle(const PlanRobot& idle,
                                             const std::vector<PlanCluster>& clusters,
                                             const std::vector<uint32_t>& held,
                                             const PlannerOptions& options) {
  if (auto ok = check({idle}, clusters); !ok) return make_unexpected(ok.error());
  const std::unordered_set<uint32_t> taken(held.begin(), held.end());
  std::vector<PlanCluster> free;
  for (const PlanCluster& c : clusters)
    if (taken.count(c.id) == 0 && (c.robot_types & idle.type_bit) != 0) free.push_back(c);
  auto team = plan_tsga({idle}, free, options);
  if (!team) return make_unexpected(team.error());
  return team->robots.front();
}

Result<TeamPlan, std::string> plan_nnb(const std::vector<PlanRobot>& robots,
                                       const std::vector<PlanCluster>& clusters,
                                       const PlannerOptions& options) {
  if (auto ok = check(robots, clusters); !ok) return make_unexpected(ok.error());
  TeamPlan plan;
  auto paths = intra_paths(clusters, options);
  if (!paths) return make_unexpected(paths.error());
  const Allocation alloc(robots, clusters, std::move(paths).value(), options);
  std::vector<bool> reachable(clusters.size(), false);
  for (const PlanRobot& r : robots) {
    size_t best = clusters.size();
    double best_f = -1;
    for (size_t v = 0; v < clusters.size(); ++v) {
      if ((clusters[v].robot_types & r.type_bit) == 0) continue;
      reachable[v] = true;
      const double f = alloc.utility(r, r.position, v);
      if (f > best_f) {
        best_f = f;
        best = v;
      }
    }
    plan.robots.push_back(best < clusters.size() ? alloc.plan_of(r, {best})
                                                 : RobotPlan{.robot_id = r.id});
  }
  for (size_t v = 0; v < clusters.size(); ++v)
    if (!reachable[v]) plan.unassigned.push_back(clusters[v].id);
  return plan;
}

}  // namespace scancrew::tsga
