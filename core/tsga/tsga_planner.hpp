#pragma once

// High-level planners over viewpoint clusters (thesis 2.5, 3.5.1, 4.5.1): TSGA (Algorithm
// 2), dist-TSGA (Algorithm 5) and the NNB baseline (Algorithm 4), on the maxATSP engine of
// atsp.hpp and the utilities of eq. 2.3 (utility.hpp).
//
// The graph, as implemented:
//   nodes: {q_0} (the robot's position) and the clusters;
//   each cluster V has one intra-cluster path τ_lm over its viewpoints, the shortest open
//     Hamiltonian path found by the engine (a closed ATSP with a free dummy node), computed
//     once per planning call (or kept from an earlier call, IntraPathCache): it is entered at its
//     first viewpoint q_l and left at its last q_m (the thesis recomputes τ_lm per entry point; one
//     path per cluster keeps the matrix static, so one maxATSP solve per insertion);
//   d(τ_kl): the straight-line distance from U's exit to V's entry, or a caller's distance
//     (PlannerOptions::travel_distance, per robot type, e.g. the low-level planner's roadmap
//     for that type), d(τ_lm): the intra path's length;
//   f_UV = g(V)·exp(−λ_tc·d(τ_kl) − λ_ic·d(τ_lm)), λ per robot (heterogeneous teams).
// TSGA: clusters ranked by their distance to the nearest robot that can reach them
// (ascending); each goes to the robot k maximising maxATSP(U^k ∪ V) − p^k (the thesis;
// PlannerOptions::gain kArrival measures both by the arrival-discounted sum) among those
// whose type can reach it (ties: the lower index); clusters no robot can reach are returned
// unassigned. Insertions are evaluated with a short search (insertion_iterations), each
// robot's final path polished with final_iterations.
// dist-TSGA: every robot runs the same deterministic TSGA on its own map estimate and keeps
// only its own path; on identical inputs every robot gets the partition TSGA gives.
// NNB: each robot gets the one cluster maximising f_{q_0 V} (clusters may repeat across
// robots; the low-level planners resolve conflicts, 3.5.2).
//
// Bad input: NaN or negative gains, NaN positions, duplicate cluster or robot ids, a cluster
// without viewpoints: an error naming it. No clusters or no robots: empty plans.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/enum_names.hpp"
#include "core/result.hpp"
#include "core/tsga/atsp.hpp"

namespace scancrew::tsga {

struct PlanCluster {
  uint32_t id = 0;
  double gain = 0;             // g(V)
  uint32_t robot_types = ~0u;  // bits of the robot types that can reach it
  std::vector<Eigen::Vector3d> viewpoints;
};

struct PlanRobot {
  uint32_t id = 0;
  uint32_t type_bit = 1;  // its robot type's bit
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double lambda_tc_per_m = 0.5;   // table 5.3 (test arena): inter-cluster penalty
  double lambda_ic_per_m = 0.01;  // intra-cluster penalty
};

// A cluster's intra-cluster path τ_lm: its viewpoints in visiting order and its length.
struct IntraPath {
  std::vector<Eigen::Vector3d> viewpoints;
  std::vector<uint32_t> indices;  // of the viewpoints in the cluster's list
  double length_m = 0;
};

// Intra-cluster paths kept from one planning call to the next: a cluster whose viewpoints
// are the same as before (positions and order, bit for bit) gets the path found then, which
// is the path the engine would find again (it is deterministic for a matrix, a seed and an
// iteration budget; both are part of the key). The ISE extractor re-sends every cluster at
// each map update and most of them have not changed; the powerplant's largest ones hold
// hundreds of viewpoints. A path not asked for during a generation (new_generation(), one
// per planning call of the caller) is dropped at the end of the next one. Not thread safe.
class IntraPathCache {
 public:
  struct Stats {
    uint64_t hits = 0;
    uint64_t misses = 0;
    double solve_ms = 0;  // spent finding the paths of the misses
  };
  // the path of these viewpoints, or null
  const IntraPath* find(const std::vector<Eigen::Vector3d>& viewpoints, int iterations,
                        uint64_t seed);
  void insert(const std::vector<Eigen::Vector3d>& viewpoints, int iterations, uint64_t seed,
              IntraPath path, double solve_ms);
  void new_generation();
  const Stats& stats() const { return stats_; }
  size_t size() const { return current_.size() + previous_.size(); }

 private:
  struct Entry {
    std::vector<Eigen::Vector3d> viewpoints;
    int iterations = 0;
    uint64_t seed = 0;
    IntraPath path;
  };
  using Map = std::unordered_multimap<uint64_t, Entry>;
  static uint64_t key(const std::vector<Eigen::Vector3d>& viewpoints, int iterations,
                      uint64_t seed);
  static Map::iterator match(Map& map, uint64_t k, const std::vector<Eigen::Vector3d>& viewpoints,
                             int iterations, uint64_t seed);
  Map current_;   // asked for in this generation
  Map previous_;  // asked for in the one before, not yet in this one
  Stats stats_;
};

struct PlannerOptions {
  int insertion_iterations = 20;  // ILS kicks per insertion evaluation
  int final_iterations = 300;     // ILS kicks for each robot's final path
  uint64_t seed = 1;
  // d(τ_kl) from a cluster's exit to the next one's entry for a robot of type `type_bit`
  // (PlanRobot::type_bit: a ground robot's way is not a multirotor's): null = straight line;
  // else e.g. the low-level planner's roadmap distance for that type. Non-finite =
  // unreachable (the arc's f is 0). Called O(n²) times per maxATSP solve: memoise an
  // expensive one.
  std::function<double(uint32_t type_bit, const Eigen::Vector3d& from, const Eigen::Vector3d& to)>
      travel_distance;
  // intra-cluster paths kept across calls (null: found again at every call); the caller
  // owns it and starts a generation per planning call
  IntraPathCache* intra_paths = nullptr;
  // TSGA's insertion gain (not the tour order, which stays the maxATSP of eq. 2.3):
  //   kArc (the thesis): maxATSP(U^k ∪ V) − p^k, each arc's f discounted by its own hop;
  //   kArrival: the same order's Σ g·exp(−λ_tc·D − λ_ic·d(τ_lm)) with D the way along the
  //   tour to the cluster's entry (hops and intra paths), before and after. A cluster deep
  //   in a busy robot's tour is worth little to it, so it goes to the robot that gets there
  //   first: with arc gains the robot whose tour passes near held the whole neighbourhood
  //   while its teammates idled (Step 10: idle 10-42 % of ground teams' time). The ground profile's
  //   choice; it made the powerplant's UAV trio worse (docs/tsga.md), so the default is the
  //   thesis's.
  enum class Gain { kArc, kArrival };
  Gain gain = Gain::kArc;
};

// allocation_gain: arc | arrival
inline constexpr EnumNames<PlannerOptions::Gain, 2> kGainNames = {
    {{PlannerOptions::Gain::kArc, "arc"}, {PlannerOptions::Gain::kArrival, "arrival"}}};

// A viewpoint of a plan: its cluster and its index in the cluster's viewpoint list.
struct ViewpointRef {
  uint32_t cluster_id = 0;
  uint32_t index = 0;
};

struct RobotPlan {
  uint32_t robot_id = 0;
  std::vector<uint32_t> clusters;            // cluster ids in visiting order
  std::vector<Eigen::Vector3d> viewpoints;   // the path's viewpoints in order
  std::vector<ViewpointRef> viewpoint_refs;  // where each of them comes from
  std::vector<double> utilities;             // f of each arc taken (per cluster)
  double utility = 0;                        // p = maxATSP(U^k)
};

struct TeamPlan {
  std::vector<RobotPlan> robots;     // one per input robot, in input order
  std::vector<uint32_t> unassigned;  // clusters no robot type can reach
};

Result<TeamPlan, std::string> plan_tsga(const std::vector<PlanRobot>& robots,
                                        const std::vector<PlanCluster>& clusters,
                                        const PlannerOptions& options = {});
// The robot `self` (an id in robots) keeps its own path of the TSGA allocation.
Result<RobotPlan, std::string> plan_dist_tsga(uint32_t self, const std::vector<PlanRobot>& robots,
                                              const std::vector<PlanCluster>& clusters,
                                              const PlannerOptions& options = {});
// Asynchronous reallocation (3.5.1): a robot that has become idle gets the clusters that no
// other robot holds (`held`: the cluster ids in the other robots' current plans) and that
// its type can reach, ordered by maxATSP as in TSGA with the idle robot alone.
Result<RobotPlan, std::string> plan_for_idle(const PlanRobot& idle,
                                             const std::vector<PlanCluster>& clusters,
                                             const std::vector<uint32_t>& held,
                                             const PlannerOptions& options = {});
Result<TeamPlan, std::string> plan_nnb(const std::vector<PlanRobot>& robots,
                                       const std::vector<PlanCluster>& clusters,
                                       const PlannerOptions& options = {});

}  // namespace scancrew::tsga
