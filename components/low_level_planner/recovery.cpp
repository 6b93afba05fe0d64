#include "components/low_level_planner/recovery.hpp"

#include <cmath>

#include "interfaces/eigen_conversions.hpp"

namespace scancrew::low_level_planner {

namespace {
constexpr int kDirections = 16;
}  // namespace

Recovery::Recovery(RecoveryConfig config) : config_(config), stall_(config_.stall) {}

std::optional<msg::Waypoint> Recovery::escape_pose(const msg::Waypoint& start, double from_m,
                                                   bool multirotor, double max_altitude_m,
                                                   const IsFree& is_free) const {
  // from backoff_min_m: an escape pose within the tracker's position tolerance would be
  // "reached" without a move, and the robot would back off on the spot forever
  for (double r = from_m; r <= config_.backoff_max_m + 1e-9; r += config_.backoff_step_m) {
    if (multirotor) {
      msg::Waypoint up = start;
      up.position.z += r;
      // not above the altitude band: from there no query has a valid start (a UAV of an
      // outdoor trio backed off to 44.8 m, over 40, and never planned again)
      if (up.position.z <= max_altitude_m && is_free(up)) return up;
    }
    for (int k = 0; k < kDirections; ++k) {
      // behind first: the robot stopped facing what it must not hit
      const double angle =
          start.yaw_rad + M_PI + 2 * M_PI * (k % 2 == 0 ? k / 2 : -(k + 1) / 2) / kDirections;
      msg::Waypoint w = start;
      w.position.x += r * std::cos(angle);
      w.position.y += r * std::sin(angle);
      if (is_free(w)) return w;
    }
  }
  return std::nullopt;
}

std::optional<msg::Waypoint> Recovery::nudged_goal(const msg::Waypoint& goal,
                                                   const IsFree& is_free) const {
  for (double r = config_.backoff_step_m; r <= config_.goal_nudge_max_m + 1e-9;
       r += config_.backoff_step_m)
    for (int k = 0; k < kDirections; ++k) {
      const double angle = 2 * M_PI * k / kDirections;
      msg::Waypoint w = goal;
      w.position.x += r * std::cos(angle);
      w.position.y += r * std::sin(angle);
      if (is_free(w)) return w;
    }
  return std::nullopt;
}

std::optional<Recovery::StuckRound> Recovery::count_no_path(const Eigen::Vector3d& at) {
  if (config_.stuck_backoff_m <= 0) return std::nullopt;
  // one place: within backoff_max_m of the first failure (each round backs off farther)
  if (!stuck_ || (at - stuck_->at).norm() > config_.backoff_max_m) stuck_ = StuckSpot{.at = at};
  if (++stuck_->failures < config_.max_consecutive_failures) return std::nullopt;
  stuck_->failures = 0;
  ++stuck_->rounds;
  return StuckRound{.from_m = config_.stuck_backoff_m * stuck_->rounds};
}

bool Recovery::stalled_again(uint64_t plan_id, size_t goal, const Eigen::Vector3d& at) {
  const bool again = stall_goal_ && stall_goal_->plan_id == plan_id && stall_goal_->goal == goal &&
                     (at - stall_goal_->at).norm() <= config_.backoff_max_m;
  if (again)
    stall_goal_.reset();
  else
    stall_goal_ = StallGoal{.plan_id = plan_id, .goal = goal, .at = at};
  return again;
}

std::optional<Recovery::Detour> Recovery::over_detour_budget(uint64_t plan_id, size_t goal,
                                                             double travelled_m, double planned_m,
                                                             double left_m) {
  if (config_.max_detour_factor <= 0) return std::nullopt;
  if (!goal_cost_ || goal_cost_->plan_id != plan_id || goal_cost_->goal != goal) {
    goal_cost_ = GoalCost{
        .plan_id = plan_id, .goal = goal, .travelled_at_m = travelled_m, .first_m = planned_m};
    return std::nullopt;
  }
  Detour d;
  d.travelled_m = travelled_m - goal_cost_->travelled_at_m;
  d.way_m = d.travelled_m + left_m;
  d.budget_m = config_.max_detour_factor * goal_cost_->first_m + config_.path_recheck_horizon_m;
  d.first_m = goal_cost_->first_m;
  if (d.way_m <= d.budget_m) return std::nullopt;
  return d;
}

}  // namespace scancrew::low_level_planner
