#pragma once

// HighLevelPlanner: the planning module's high-level planner (thesis 2.5.2, 3.5.1, 4.5.1).
// On every cluster update (`clusters`, msg::ViewpointClusters, from the ise_extractor) it
// allocates the clusters to the team with the configured algorithm (tsga_planner.hpp) and
// publishes
//   plan  msg::TeamPlan: per robot the cluster tour, its viewpoints (with yaw and cluster
//         id), the arc utilities, p = maxATSP(U), and C_start (the ISE centres the tour's
//         viewpoints see, from `ises`, for the low-level planner's UtilityCheck).
// algorithm:
//   tsga       Algorithm 2, centralized: one instance (per_robot: false) plans for the whole
//              team and publishes every robot's sequence;
//   dist_tsga  Algorithm 5: one instance per robot, on that robot's own map estimate; the
//              same allocation, but it publishes only its robot's sequence;
//   nnb        Algorithm 4 baseline: each robot's best single cluster (all robots' when
//              centralized, the own robot's when per robot).
// The robots' positions come from each team member's `pose` port (its remap in the member's
// namespace: pose: pose_gt gives /<namespace>/pose_gt); before the first one, the launch file's
// start pose. Each member's `/<namespace>/robot_state` (msg::RobotState) is watched too:
//   mode kIdle while the planner holds a plan for it: asynchronous reallocation (3.5.1): the
//     robot gets the clusters no teammate holds (plan_for_idle); centralized tsga only, as
//     in the thesis; dist_tsga replans the whole allocation instead;
//   (`/<namespace>/replan_request`, msg::ReplanRequest: the low-level planner asks for an
//     update, Algorithms 1/3/6, with its reason): a new plan from the latest clusters at once;
//   mode kLost (the dds_bridge's word for a teammate whose process died): the member is left
//     out of the plans (plan_robots(): no tour, an empty sequence in the TeamPlan) and the
//     whole team is re-planned at once, its clusters going to the others; every instance
//     does so (dist_tsga: each plans for the team and keeps its own sequence, so they stay
//     in agreement). Any other state after kLost brings it back, with a re-plan of the team.
//     A per-robot instance never counts its own robot lost. With every robot lost nothing
//     is planned (logged once).
//   idle_teammate_s > 0 (dist_tsga; not in the thesis): a teammate idle (kIdle or kDone)
//     for that long is planned without as well, until it moves again. Each robot plans on
//     its own map: a cluster this robot sees may be missing from the idle teammate's map,
//     and the allocation that gives it to the teammate would leave it unvisited for good
//     (seen as a stalled three-process arena run; docs/tsga.md).
// min_replan_period_s (sim time, from the message stamps) bounds how often cluster updates
// are planned; requests and idle robots are served at once.
// keep_intra_paths (default true): a cluster whose viewpoints have not changed since the
// last plan keeps its intra-cluster path (IntraPathCache); the plans are the same either
// way, only the time differs.
//
// d(τ_kl), the travel from a cluster's exit (or the robot) to the next cluster's entry in
// f of eq. 2.3 (inter_cluster_distance):
//   euclidean  the straight line;
//   roadmap    the low-level planner's path length, as in the thesis: a MotionPlanner of
//              its own (LazyPRM* roadmap, core/motion/motion_planner.hpp) follows
//              the `map` topic (msg::MapUpdate; remap it to the robot's or the team's map)
//              and, per plan, one roadmap_distances() call per kind and starting point gives
//              its distances to every viewpoint (memoised for the plan's maxATSP solves;
//              unreachable: +inf, the arc's f is 0). Until the first map, and from a point
//              whose body collides, the straight line (logged once). The planner's keys are
//              the low-level planner's (read_planner_config: one YAML block serves both);
//              there is one planner per robot kind in the team (robot_type ignored), and
//              each robot's arcs are measured on its kind's roadmap (the hook gets the
//              robot's type bit; the memo keys rows by type and starting point): in a team
//              that mixes ground robots and multirotors a wall is a detour for the one and
//              not for the other.
//
// Parameters: algorithm, inter_cluster_distance (euclidean | roadmap),
// `<type>_lambda_tc_per_m` and `<type>_lambda_ic_per_m` for ground and multirotor,
// insertion_iterations, final_iterations, seed, allocation_gain (arc: the thesis, default |
// arrival; PlannerOptions::gain), min_replan_period_s, keep_intra_paths, and
// with roadmap the
// low-level planner's keys (docs/low_level_planner.md). Bad clusters (NaN gain, duplicate
// ids) or poses: the update is skipped with an error logged once per kind; the last plan
// stands.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.hpp"
#include "core/motion/planner_config.hpp"
#include "core/tsga/tsga_planner.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::motion {
class MotionPlanner;
}  // namespace scancrew::motion

namespace scancrew::high_level_planner {

using tsga::IntraPathCache;
using tsga::PlanCluster;
using tsga::PlannerOptions;
using tsga::PlanRobot;
using tsga::TeamPlan;

// algorithm: tsga (centralized) | dist_tsga (on every robot) | nnb
enum class Algorithm : uint8_t { kTsga, kDistTsga, kNnb };
inline constexpr EnumNames<Algorithm, 3> kAlgorithmNames = {
    {{Algorithm::kTsga, "tsga"}, {Algorithm::kDistTsga, "dist_tsga"}, {Algorithm::kNnb, "nnb"}}};

// inter_cluster_distance: euclidean (the straight line) | roadmap (the low-level planner's)
enum class InterClusterDistance : uint8_t { kEuclidean, kRoadmap };
inline constexpr EnumNames<InterClusterDistance, 2> kInterClusterDistanceNames = {
    {{InterClusterDistance::kEuclidean, "euclidean"}, {InterClusterDistance::kRoadmap, "roadmap"}}};

class HighLevelPlanner final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "TSGA / dist-TSGA / NNB allocation of viewpoint clusters (thesis 3.5.1, 4.5.1)";
  struct Penalties {
    double lambda_tc_per_m = 0;
    double lambda_ic_per_m = 0;
  };
  struct Config {
    Algorithm algorithm = Algorithm::kTsga;
    InterClusterDistance inter_cluster_distance = InterClusterDistance::kEuclidean;
    // table 5.3 (real-world ground robots) and table 2.2 (Powerplant UAV, shortest path)
    Penalties ground{.lambda_tc_per_m = 0.5, .lambda_ic_per_m = 0.01};
    Penalties multirotor{.lambda_tc_per_m = 0.3, .lambda_ic_per_m = 0.03};
    PlannerOptions options;
    double min_replan_period_s = 0;
    bool keep_intra_paths = true;
    double idle_teammate_s = 0;  // dist_tsga: plan without a teammate idle this long; 0: never
    // inter_cluster_distance: roadmap: the low-level planner's keys (robot_type ignored:
    // each kind in the team gets a planner of its own kind)
    motion::PlannerConfig roadmap;
  };
  static Config read_config(ParamReader& p);

  HighLevelPlanner(ComponentContext context, Config config);
  ~HighLevelPlanner() override;

  struct Stats {
    uint64_t plans = 0;          // published
    uint64_t reallocations = 0;  // to idle robots
    uint64_t lost_replans = 0;   // re-plans for a member lost or back
    uint64_t requests = 0;       // replanning requests answered
    uint64_t skipped = 0;        // updates refused (bad input) or throttled
    double mean_ms = 0, max_ms = 0;
    // inter_cluster_distance: roadmap
    uint64_t roadmap_queries = 0;       // roadmap_distances() calls (one per starting point)
    uint64_t straight_fallbacks = 0;    // starting points measured by the straight line
    double roadmap_ms = 0;              // in roadmap_distances(), all plans
    IntraPathCache::Stats intra_paths;  // keep_intra_paths: kept / found again
  };
  const Stats& stats() const { return stats_; }

 private:
  struct Member {
    uint32_t id = 0;
    uint32_t type_bit = 1;
    Penalties penalties;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double yaw_rad = 0;
    msg::RobotState::Mode mode = msg::RobotState::Mode::kIdle;
    int64_t idle_since_ns = -1;  // -1: not idle (kIdle or kDone)
  };

  Result<void, std::string> on_configure() override;
  // inter_cluster_distance: roadmap: roadmaps_ and their `map` subscription
  Result<void, std::string> configure_roadmaps();
  void on_deactivate() override;
  void on_clusters(const msg::ViewpointClusters& clusters);
  void on_robot_state(size_t member, const msg::RobotState& state);
  void on_replan_request(size_t member, const msg::ReplanRequest& request);
  // Whether the member's latest state is kLost (never this per-robot instance's own robot).
  bool lost(size_t member) const;
  // A teammate idle for idle_teammate_s at plan_stamp_ns_ (dist_tsga, never the own robot).
  bool idle_too_long(size_t member) const;
  // Plans from the latest clusters and publishes; `idle`: reallocate to that member only.
  void plan(int64_t stamp_ns, std::optional<size_t> idle);
  // The members planned for (those not lost), in member order, and their PlanRobots in the
  // same order (TeamPlan::robots of a plan follows it; last_ is indexed by member).
  std::vector<size_t> plan_members() const;
  std::vector<PlanRobot> plan_robots() const;
  // The configured options, with the memoised roadmap distance when it is chosen and a map
  // has come.
  PlannerOptions plan_options();
  // The plan's sequences (only: that robot's alone).
  void publish(const TeamPlan& plan, int64_t stamp_ns, std::optional<size_t> only = std::nullopt);
  void fail_once(const std::string& kind, const std::string& message);
  void warn_once(const std::string& kind, const std::string& message);

  Config config_;
  bool per_robot_ = false;
  int64_t plan_stamp_ns_ = 0;  // the stamp of the plan being made (idle_too_long)
  std::vector<Member> members_;
  std::optional<msg::ViewpointClusters> clusters_;
  std::vector<PlanCluster> plan_clusters_;
  std::optional<msg::IseSet> ises_;
  TeamPlan last_;  // the plan in force, one RobotPlan per member
  std::optional<int64_t> last_plan_stamp_ns_;
  Publisher<msg::TeamPlan> plan_pub_;
  uint64_t plan_id_ = 0;
  std::map<std::string, bool> failures_logged_;
  IntraPathCache intra_paths_;
  Stats stats_;
  double ms_sum_ = 0;
  // inter_cluster_distance: roadmap: one planner per robot kind in the team, by type bit
  std::map<uint32_t, std::unique_ptr<motion::MotionPlanner>> roadmaps_;
  bool have_map_ = false;
};

}  // namespace scancrew::high_level_planner
