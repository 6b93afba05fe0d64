#pragma once

// LowLevelPlanner: a robot's low-level planner (thesis 2.5.3 Algorithm 1, 3.5.2 Algorithm 3,
// 4.5.2 Algorithm 6). It follows the tour of viewpoints the high-level planner gives it,
// one goal q at a time: plans a collision-free path to q with LazyPRM* on the latest map
// (motion_planner.hpp) and sends it to the tracker; checks GoalReached, UtilityCheck,
// ObstacleCheck, TrafficPolicy and (distributed teams) RedundancyCheck (checks_config.hpp);
// and asks the high-level planner for a new tour when they say so.
//
// Ports (relative: in the robot's namespace; remap `plan` to /plan for a centralized team)
//   in   plan          msg::TeamPlan     the sequence with this robot's id; a new one is put
//                                        on hold until the current goal is reached (2.5.3
//                                        item 2), taken at once when idle or waiting for it
//   in   map           msg::MapUpdate   the robot's map (its estimate in distributed mode)
//   in   ises          msg::IseSet       C, for UtilityCheck
//   in   pose          msg::Odometry     the robot's pose (remap: pose_gt, or odom from vio)
//   in   /<ns>/robot_state, /<ns>/local_path, /<ns>/tour of every teammate (traffic policy,
//        redundancy check)
//   out  local_path    msg::LocalPath    to the tracker (plan_id grows per path)
//   out  maneuver      msg::Maneuver     stop (obstacle, traffic), step aside, resume
//   out  robot_state   msg::RobotState   every control period: pose, velocity, mode
//                                        (kIdle: no tour; kPlanning: waiting for a new
//                                        plan, which the high-level planner answers;
//                                        kMoving, kWaiting, kSteppingAside, kStopped),
//                                        tour plan id, goal cluster, next viewpoint index,
//                                        viewpoints left, path length travelled
//   out  tour          msg::TeamPlan     the tour followed (one sequence), for teammates
//                                        (not created for a robot alone)
//   out  skipped_goal  msg::Odometry     each viewpoint skipped (no path, stall, detour):
//                                        the ISE extractor counts it as a visit
//   out  replan_request msg::ReplanRequest a request for a new tour, with its reason
//
// A goal it cannot plan to (no path, goal in collision or unknown space) is skipped,
// logged once per kind; after max_consecutive_failures skips it asks for a new plan. A
// start in collision (the robot stopped close to a surface it just discovered) is left by
// backing off to the nearest free pose, then the goal is planned again; with no free pose
// near, it asks for a new plan. A stale map (kMapStale) waits for the next one. A request
// (replan_request) unanswered for replan_timeout_s is sent again, marked repeated.
//
// Parameters: control_period_s, traffic_policy, redundancy_check,
// max_consecutive_failures, replan_timeout_s, backoff_max_m, backoff_step_m, backoff_min_m,
// goal_nudge_max_m, path_recheck_horizon_m, stall_timeout_s, stall_min_progress_m,
// max_detour_factor,
// `<kind>_nominal_speed_mps`,
// `<kind>_traffic_radius_m`, the planner core's keys
// (read_planner_config: robot_type is the launch file's kind) and the checks' keys
// (read_checks_config), docs/low_level_planner.md.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "components/low_level_planner/recovery.hpp"
#include "components/low_level_planner/tour.hpp"
#include "core/motion/checks_config.hpp"
#include "core/motion/motion_planner.hpp"
#include "core/motion/stall_watch.hpp"
#include "core/motion/traffic_policy.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/map_update.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::low_level_planner {

// The motion core's types, by the names the component has always used.
using motion::ChecksConfig;
using motion::FreeSpaceQuery;
using motion::MotionPlanner;
using motion::ObstacleCheckResult;
using motion::PlannerConfig;
using motion::PlanRequest;
using motion::PlanResult;
using motion::PlanStats;
using motion::PlanStatus;
using motion::RedundancyResult;
using motion::RobotKind;
using motion::StallConfig;
using motion::TrafficAction;
using motion::TrafficAgent;
using motion::TrafficDecision;
using motion::TrafficPolicy;
using motion::UtilityStatus;

using ReplanReason = msg::ReplanRequest::Reason;

class LowLevelPlanner final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "follows the tour: LazyPRM* paths to each viewpoint, goal / utility / obstacle checks, "
      "traffic policy, redundancy check, replanning requests (thesis 2.5.3, 3.5.2, 4.5.2)";
  struct Config {
    double control_period_s = 0.1;
    bool traffic_policy = true;
    bool redundancy_check = false;  // distributed teams (Algorithm 6)
    int max_consecutive_failures = 3;
    double replan_timeout_s = 10.0;
    // a start in collision: back off to the nearest free pose within backoff_max_m
    // (rings backoff_step_m apart from backoff_min_m, 16 directions; a multirotor also
    // tries up), then plan. backoff_min_m must exceed the tracker's position tolerance
    // (0.1 m): a closer pose is "reached" without moving.
    double backoff_max_m = 1.0, backoff_step_m = 0.1, backoff_min_m = 0.2;
    // a goal whose body overlaps an obstacle moves to the nearest free pose (same yaw) within
    // this distance (rings backoff_step_m apart) before it is skipped: the ISE extractor's
    // feasibility (voxel centres in a disc) and LazyPRM*'s (FCL, the voxel boxes against
    // the ellipse) differ at the edges, and a skipped viewpoint came back in every new plan.
    // 0: skip at once.
    double goal_nudge_max_m = 0.3;
    // stuck_backoff_m > 0 (not in the thesis): after max_consecutive_failures queries in a
    // row without a path (timeout or planner_error) from one place (within backoff_max_m of where
    // the run of failures began), whatever the goals and tours, the roadmap is dropped and the
    // robot backs off (escape_pose) at least stuck_backoff_m times the number of such
    // rounds there, up to backoff_max_m; then it plans to the same goal again. A path
    // found ends the count. A UAV pressed in
    // under an overhang failed every query from one spot for 120 s simulated (powerplant
    // trio, docs/missions.md), a second of planning each. 0: never (ask for a new plan, as
    // after any max_consecutive_failures failures).
    double stuck_backoff_m = 0.0;
    // at each new map snapshot, the local path ahead of the robot is checked again out to
    // this arc length (path_recheck.hpp); blocked: planned again from where the robot is.
    // About the camera's range: farther, the map changes again before the robot gets there.
    // 0: never (the thesis's behaviour).
    double path_recheck_horizon_m = 5.0;
    // a robot whose way left along its path has not shrunk by stall_min_progress_m for
    // stall_timeout_s (stall_watch.hpp): planned again from where it is; a second time on
    // the same goal, within backoff_max_m: the goal is skipped. stall_timeout_s 0: never.
    // Not in the thesis.
    StallConfig stall;
    // the detour budget (not in the thesis): a goal whose way (travelled since its first
    // path, plus the straight line left, checked at each new path to it) grows past
    // max_detour_factor times the first path planned to it plus path_recheck_horizon_m
    // (within the camera's range the map changes anyway) is skipped. The allocation priced the goal
    // at that first length; a newer map that keeps blocking the way (unknown space read as free)
    // turns it into a chase round a building (a UAV of the powerplant trio flew 529 m after one
    // goal, 35 paths blocked, Step 10). 0: never.
    double max_detour_factor = 2.0;
    // the traffic policy's view of every robot of the kind: nominal speed (table 5.3: 0.5
    // m/s ground; 2.6.1: 0.6 m/s multirotor) and the radius holding its body (the ground
    // robot of sim/robot_model.hpp: 0.44 x 0.40 m; a multirotor with rotors: 0.5 m)
    double ground_nominal_speed_mps = 0.5, multirotor_nominal_speed_mps = 0.6;
    double ground_traffic_radius_m = 0.3, multirotor_traffic_radius_m = 0.5;
    PlannerConfig planner;
    // both kinds' defaults, the launch file's keys over each; the robot's kind picks one
    ChecksConfig ground_checks, multirotor_checks;
  };
  static Config read_config(ParamReader& p);

  LowLevelPlanner(ComponentContext context, Config config);
  ~LowLevelPlanner() override;

  struct Stats {
    uint64_t paths = 0;          // local paths sent
    uint64_t plan_failures = 0;  // queries without a path
    uint64_t goals_reached = 0;
    uint64_t goals_skipped = 0;
    uint64_t tours = 0;    // tours taken
    uint64_t replans = 0;  // requests sent, all reasons
    uint64_t emergency_stops = 0;
    uint64_t backoffs = 0;        // starts in collision left by backing off
    uint64_t stuck_backoffs = 0;  // backed off from a spot with no path out (stuck_backoff_m)
    uint64_t goals_nudged = 0;    // goals in collision moved to a free pose near them
    uint64_t paths_blocked = 0;   // local paths a newer map blocked ahead: planned again
    uint64_t traffic_holds = 0;   // stop or step aside maneuvers
    uint64_t redundancies = 0;
    uint64_t stalls = 0;   // no progress on a path for stall_timeout_s (StallWatch)
    uint64_t detours = 0;  // goals skipped over the detour budget
    double plan_ms_sum = 0, plan_ms_max = 0;
    PlanStats slowest_plan;    // where the slowest query's time went
    double path_length_m = 0;  // travelled
  };
  const Stats& stats() const { return stats_; }
  msg::RobotState::Mode mode() const { return mode_; }

  // What the planner does with its tour. Transitions go through enter() only; tick() acts
  // by the state. The mode the team sees (RobotState::mode) says more (waiting for a map,
  // held by the traffic policy, stepping aside) and is set as the tick goes.
  enum class State : uint8_t {
    kIdle,          // no tour, or its goals are done: holds its place, steps aside for a
                    // teammate (make_way); a new plan is taken at once
    kToPlan,        // the tour's next goal needs a path: the follow checks, then LazyPRM*
    kFollowing,     // a local path to the goal is out: goal reached, path re-check,
                    // obstacle, traffic, stall
    kBackingOff,    // a path to a free pose nearby is out (Recovery); reached: kToPlan
    kAwaitingPlan,  // a request for a new tour is out (Request); a new plan answers it
  };
  State state() const { return state_; }
  void summarize(RunSummary& into) const override {
    into.planners[robot_id()] = {
        .tours = stats_.tours, .goals_reached = stats_.goals_reached, .replans = stats_.replans};
  }

 private:
  struct Teammate {
    uint32_t id = 0;
    double nominal_speed_mps = 0, traffic_radius_m = 0;  // of its kind
    bool seen = false;
    msg::RobotState state;
    std::vector<msg::Waypoint> local_path;
    std::optional<msg::PathSequence> tour;
    uint64_t tour_plan_id = 0;
  };

  Result<void, std::string> on_configure() override;
  Result<void, std::string> configure_planner();
  void create_ports();
  void subscribe_teammates();
  void on_deactivate() override;
  void on_plan(const msg::TeamPlan& plan);
  void on_pose(const msg::Odometry& odom);
  void tick();
  // Steps of one tick, in the order of Algorithms 1, 3 and 6.
  bool follow_checks();  // redundancy, utility: true when a new plan was asked for
  void plan_to_goal();
  // A path found: sent to the tracker, unless the goal is over its detour budget.
  void follow_path(const PlanRequest& request, const std::vector<msg::Waypoint>& path);
  // None: back off (start in collision, stuck), nudge the goal, or skip it.
  void plan_failed(const PlanRequest& request, const PlanResult& r);
  // stuck_backoff_m: counts a failure without a path (timeout, planner_error) from `start`; true
  // when the robot backs off because of it (the path to the escape pose is out).
  bool back_off_if_stuck(const msg::Waypoint& start);
  // Sends the two-waypoint path from start to the free pose `escape` (a back-off).
  void send_backoff(const msg::Waypoint& start, const msg::Waypoint& escape);
  // The nearest free pose around the robot (in a fixed order), if any: clear of the
  // teammates, on rings from_m, + backoff_step_m, ... up to backoff_max_m.
  std::optional<msg::Waypoint> escape_pose(const msg::Waypoint& start, double from_m) const;
  // The nearest free pose to `goal` (is_free), same yaw, within goal_nudge_max_m.
  std::optional<msg::Waypoint> nudged_goal(const msg::Waypoint& goal) const;
  void park_lost_teammates();  // the lost teammates' bodies to the motion planner
  // A path out: the back-off's end, else the goal, the path re-check, an obstacle ahead and
  // the traffic policy, in that order (the first three end the tick's watch when they act).
  void watch_motion();
  void watch_backoff();   // the escape pose reached: plan to the goal again
  bool at_goal();         // GoalReached: the next goal (or the plan held back)
  bool path_blocked();    // a newer map blocks the path ahead: plan again from here
  bool obstacle_ahead();  // ObstacleCheck: stop, ask for a new plan
  void watch_traffic();   // TrafficPolicy: proceed, wait, step aside, resume, give up
  void watch_stall();     // no progress on the path: plan again, then skip the goal
  // At a path to the current goal (`planned_m` long, the goal `left_m` away in a straight
  // line): the first records the budget; a later one is over it when the way travelled
  // since the first plus left_m (a lower bound of the rest: a sampling planner's path
  // may be twice the shortest) exceeds max_detour_factor x the first + path_recheck_horizon_m.
  bool over_detour_budget(double planned_m, double left_m);
  // Skips the current goal after it was planned to (stall, detour): takes the plan held
  // back for it, or asks for one when the tour is done.
  void skip_goal(const char* why);
  // A skipped goal, on `skipped_goal`: the ISE extractor counts it as a visit.
  void report_skipped(const msg::Waypoint& goal);
  TrafficDecision traffic_decision(std::vector<Eigen::Vector3d> path);
  void make_way();  // an idle robot steps aside for a teammate it blocks
  void take(const msg::PathSequence& sequence, uint64_t plan_id);
  void request_replan(ReplanReason reason, uint32_t because_of, const std::string& detail);
  void send_request(bool repeated);
  void send_maneuver(msg::Maneuver::Kind kind, const msg::Waypoint& aside, uint32_t because);
  void publish_state();
  size_t remaining_ises() const;
  TrafficAgent self_agent() const;
  double now_s();
  void log_once(const std::string& key, const std::string& message);
  // The one place the state changes (logged at debug level).
  void enter(State next);
  // A local path is out to the tracker (to the goal or a back-off; when awaiting a plan,
  // one was out when the request went).
  bool path_is_out() const;
  // At debug level (SCANCREW_LOG=debug): each change of the traffic decision, with why.
  void log_traffic(const TrafficDecision& d);

  Config config_;
  ChecksConfig checks_;
  double nominal_speed_mps_ = 0, traffic_radius_m_ = 0;  // the robot's kind's
  std::optional<MotionPlanner> planner_;
  std::optional<TrafficPolicy> traffic_;
  std::shared_ptr<const tsdf::MapSnapshot> map_;
  std::vector<uint64_t> current_ises_;  // sorted voxel keys of C
  bool have_ises_ = false;
  std::optional<msg::Odometry> pose_;
  std::optional<msg::Vec3> last_position_;
  std::vector<Teammate> teammates_;

  std::optional<Tour> tour_;
  std::optional<std::pair<msg::PathSequence, uint64_t>> pending_;  // sequence, plan id
  uint64_t last_plan_id_ = 0;                                      // the newest plan seen
  State state_ = State::kIdle;
  struct Request {               // kAwaitingPlan: the request out
    uint64_t after_plan_id = 0;  // the first plan newer than this answers it
    double since_s = 0;          // sent (again) at
    bool path_out = false;       // a local path was out when it went
    ReplanReason reason = ReplanReason::kUtility;
    uint32_t because_of_robot = 0;
    bool unsent = true;  // sent at the end of the tick (send_request)
  };
  std::optional<Request> request_;
  struct Backoff {  // kBackingOff: the free pose it backs off to, and from where
    msg::Waypoint escape;
    msg::Vec3 from;
  };
  std::optional<Backoff> backoff_;
  Recovery recovery_;
  std::vector<msg::Waypoint> local_path_;  // the last one sent (the traffic policy's)
  bool map_unchecked_ = false;             // a snapshot newer than the path's last check
  uint32_t held_by_ = 0;  // the teammate the traffic policy yields to this tick (0: none)
  int consecutive_failures_ = 0;
  uint64_t local_path_id_ = 0;
  msg::RobotState::Mode mode_ = msg::RobotState::Mode::kIdle;
  msg::RobotState::Mode published_mode_ = msg::RobotState::Mode::kIdle;  // the last sent
  msg::Maneuver::Kind last_maneuver_ = msg::Maneuver::Kind::kResume;
  TrafficDecision last_traffic_;  // the last one logged (log_traffic)
  struct AsideSent {
    Eigen::Vector3d point;
    double at_s = 0;
  };
  std::optional<AsideSent> aside_sent_;  // an idle robot's last step-aside (make_way)

  Publisher<msg::LocalPath> path_pub_;
  Publisher<msg::Maneuver> maneuver_pub_;
  Publisher<msg::RobotState> state_pub_;
  Publisher<msg::TeamPlan> tour_pub_;
  Publisher<msg::Odometry> skipped_pub_;
  Publisher<msg::ReplanRequest> request_pub_;
  std::vector<std::string> logged_;
  Stats stats_;
};

}  // namespace scancrew::low_level_planner
