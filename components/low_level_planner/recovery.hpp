#pragma once

// Recovery: the low-level planner's ways out when following the tour fails (none is in the
// thesis, whose Algorithm 1 skips a goal without a path and otherwise waits for GoalReached;
// docs/low_level_planner.md gives the incident behind each):
//   back-off   a start in collision: a free pose on rings around the robot (escape_pose)
//   stuck      max_consecutive_failures queries without a path from one spot: a back-off
//              farther at each round (count_no_path)
//   nudge      a goal in collision: the nearest free pose near it (nudged_goal)
//   stall      no progress along the path for stall_timeout_s: plan again, the second time
//              on the same goal skip it (stalled, stalled_again)
//   detour     the way to a goal past max_detour_factor x its first path: skip it
//              (over_detour_budget)
// It decides and remembers; the LowLevelPlanner sends the paths, counts and logs. Poses are
// tested by the caller's `is_free` (the motion planner's body test, and the teammates).

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>

#include "core/motion/stall_watch.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::low_level_planner {

struct RecoveryConfig {
  int max_consecutive_failures = 3;
  // back-off rings: backoff_step_m apart, from backoff_min_m (a start in collision) or
  // stuck_backoff_m x rounds (stuck) out to backoff_max_m; 16 directions, behind first
  double backoff_max_m = 1.0, backoff_step_m = 0.1, backoff_min_m = 0.2;
  double goal_nudge_max_m = 0.3;        // 0: a goal in collision is skipped at once
  double stuck_backoff_m = 0.0;         // 0: no stuck back-off
  double max_detour_factor = 2.0;       // 0: no detour budget
  double path_recheck_horizon_m = 5.0;  // added to the detour budget
  motion::StallConfig stall;
};

class Recovery {
 public:
  using IsFree = std::function<bool(const msg::Waypoint&)>;

  explicit Recovery(RecoveryConfig config);
  const RecoveryConfig& config() const { return config_; }

  // The nearest free pose around `start`, on rings from `from_m` out to backoff_max_m: a
  // multirotor first tries straight up (not above `max_altitude_m`), then 16 directions,
  // behind the robot first.
  std::optional<msg::Waypoint> escape_pose(const msg::Waypoint& start, double from_m,
                                           bool multirotor, double max_altitude_m,
                                           const IsFree& is_free) const;
  // The nearest free pose to `goal`, same yaw, within goal_nudge_max_m.
  std::optional<msg::Waypoint> nudged_goal(const msg::Waypoint& goal, const IsFree& is_free) const;

  // A query without a path from `at`. One spot: within backoff_max_m of where the run began.
  // A round of max_consecutive_failures there gives the distance to back off at least
  // (stuck_backoff_m x rounds, possibly past backoff_max_m: then no back-off); else nothing.
  struct StuckRound {
    double from_m = 0;
  };
  std::optional<StuckRound> count_no_path(const Eigen::Vector3d& at);
  void path_found() { stuck_.reset(); }

  // The stall watch on the way left along the path (remaining_m at now_s): true when it
  // fires. reset_stall(): not on a path this tick.
  bool stalled(double remaining_m, double now_s) { return stall_.update(remaining_m, now_s); }
  void reset_stall() { stall_.reset(); }
  // After a stall at `at` on goal `goal` of tour `plan_id`: true for the second one there
  // (within backoff_max_m of the first), which skips the goal; the first is remembered.
  bool stalled_again(uint64_t plan_id, size_t goal, const Eigen::Vector3d& at);

  // At a path to goal `goal` of tour `plan_id`, `planned_m` long, the goal `left_m` away in
  // a straight line, `travelled_m` the robot's odometer: the first path to a goal records
  // the budget; a later one is over it when the way (travelled since the first, plus
  // left_m) exceeds max_detour_factor x the first + path_recheck_horizon_m.
  struct Detour {
    double way_m = 0, travelled_m = 0, budget_m = 0, first_m = 0;
  };
  std::optional<Detour> over_detour_budget(uint64_t plan_id, size_t goal, double travelled_m,
                                           double planned_m, double left_m);

 private:
  RecoveryConfig config_;
  struct StuckSpot {  // the run of queries without a path from one spot, and its rounds
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    int failures = 0;
    int rounds = 0;
  };
  std::optional<StuckSpot> stuck_;
  motion::StallWatch stall_;
  struct StallGoal {  // where the last stall was: plan, goal index, robot position
    uint64_t plan_id = 0;
    size_t goal = 0;
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
  };
  std::optional<StallGoal> stall_goal_;
  struct GoalCost {  // the detour budget's record of the current goal
    uint64_t plan_id = 0;
    size_t goal = 0;
    double travelled_at_m = 0;  // the odometer at its first path
    double first_m = 0;         // that path's length
  };
  std::optional<GoalCost> goal_cost_;
};

}  // namespace scancrew::low_level_planner
