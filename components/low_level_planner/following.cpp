// The LowLevelPlanner following its tour (Algorithms 1, 3 and 6): the follow checks, a path
// to the next goal and what a failed query leads to (Recovery), then watching the path out
// (goal reached, path re-check, obstacle, traffic, stall) and skipping goals.

#include <cmath>
#include <cstdio>

#include "components/low_level_planner/local_path.hpp"
#include "components/low_level_planner/low_level_planner.hpp"
#include "core/motion/goal_check.hpp"
#include "core/motion/map_queries.hpp"
#include "core/motion/obstacle_check.hpp"
#include "core/motion/path_recheck.hpp"
#include "core/motion/redundancy_check.hpp"
#include "core/motion/utility_check.hpp"
#include "executors/log.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::low_level_planner {

using motion::count_remaining;
using motion::goal_reached;
using motion::obstacle_check;
using motion::occupancy_query;
using motion::PathRecheck;
using motion::recheck_path;
using motion::redundancy_check;
using motion::remaining_length_m;
using motion::utility_check;

namespace {
using Mode = msg::RobotState::Mode;
}  // namespace

bool LowLevelPlanner::follow_checks() {
  if (config_.redundancy_check) {
    std::vector<TourProgress> others;
    for (const Teammate& t : teammates_)
      if (t.seen && t.state.mode != Mode::kLost && t.tour && t.state.plan_id == t.tour_plan_id)
        others.push_back(
            tour_progress(t.id, t.state.T_world_body.position, *t.tour, t.state.path_index));
    const RedundancyResult r = redundancy_check(
        tour_progress(robot_id(), pose_->T_world_body.position, tour_->sequence, tour_->next),
        others, checks_.redundancy);
    if (r.redundancy) {
      ++stats_.redundancies;
      const uint32_t winner = r.contests.empty() ? 0 : r.contests.front().winner_id;
      request_replan(ReplanReason::kRedundancy, winner,
                     "cluster " + std::to_string(tour_->goal_cluster()) + " is robot " +
                         std::to_string(winner) + "'s");
      return true;
    }
  }
  if (have_ises_) {
    const UtilityStatus u = utility_check(tour_->c_start.size(), remaining_ises(), checks_.utility);
    if (u.update) {
      request_replan(ReplanReason::kUtility, 0,
                     std::to_string(static_cast<int>(100 * u.completed_fraction)) +
                         " % of the tour's ISEs done");
      return true;
    }
  }
  return false;
}

size_t LowLevelPlanner::remaining_ises() const {
  return count_remaining(tour_->c_start, current_ises_);
}

void LowLevelPlanner::plan_to_goal() {
  PlanRequest request;
  request.start.position = pose_->T_world_body.position;
  request.start.yaw_rad = yaw_of(pose_->T_world_body.orientation);
  request.goal = tour_->goal();
  request.pose_stamp_ns = pose_->header.stamp_ns;
  const PlanResult r = planner_->plan(request);
  if (r.first_report)
    SCANCREW_LOG_WARN("low-level planner: %s: %s", std::string(to_string(r.status)).c_str(),
                      r.message.c_str());
  stats_.plan_ms_sum += r.stats.total_ms;
  if (r.stats.total_ms > stats_.plan_ms_max) {
    stats_.plan_ms_max = r.stats.total_ms;
    stats_.slowest_plan = r.stats;
  }
  switch (r.status) {
    case PlanStatus::kOk:
      follow_path(request, r.path);
      return;
    case PlanStatus::kMapStale:
      mode_ = Mode::kWaiting;  // the next snapshot answers it
      log_once("stale", r.message + " (waiting for a newer map)");
      return;
    default:
      plan_failed(request, r);
      return;
  }
}

void LowLevelPlanner::follow_path(const PlanRequest& request,
                                  const std::vector<msg::Waypoint>& path) {
  if (over_detour_budget(
          path_length_m(request.start.position, path),
          (msg::to_eigen(request.goal.position) - msg::to_eigen(request.start.position)).norm())) {
    ++stats_.detours;
    send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);  // an old path may lead to it
    skip_goal("detour");
    return;
  }
  if (auto loan = path_pub_.loan()) {
    (*loan)->plan_id = ++local_path_id_;
    (*loan)->waypoints = path;
    (void)path_pub_.publish(std::move(*loan));
  }
  local_path_ = path;
  recovery_.path_found();
  recovery_.reset_stall();
  ++stats_.paths;
  enter(State::kFollowing);
  map_unchecked_ = false;  // planned on the newest snapshot
  consecutive_failures_ = 0;
  mode_ = Mode::kMoving;
  send_maneuver(msg::Maneuver::Kind::kResume, {}, 0);
}

void LowLevelPlanner::plan_failed(const PlanRequest& request, const PlanResult& r) {
  ++stats_.plan_failures;
  ++consecutive_failures_;
  if (r.status == PlanStatus::kStartInCollision) {
    log_once("start", r.message +
                          " (backing off to the nearest free pose; further such "
                          "cases are counted)");
    if (auto escape = escape_pose(request.start, config_.backoff_min_m)) {
      send_backoff(request.start, *escape);
      ++stats_.backoffs;
      return;
    }
    request_replan(ReplanReason::kInfeasible, 0, r.message + ", no free pose near");
    return;
  }
  if (r.status == PlanStatus::kGoalInCollision) {
    if (auto w = nudged_goal(tour_->goal())) {
      log_once("nudged", r.message +
                             " (moved to the nearest free pose within goal_nudge_max_m; further "
                             "such cases are counted)");
      tour_->sequence.viewpoints[tour_->next] = *w;
      ++stats_.goals_nudged;
      return;  // planned at the next tick
    }
  }
  log_once(std::string(to_string(r.status)),
           r.message + " (that viewpoint is skipped; further such failures are counted)");
  // no path from here, whichever the cause (a timeout or OMPL refusing the query): the
  // stuck count (stuck_backoff_m)
  const bool no_path = r.status == PlanStatus::kTimeout || r.status == PlanStatus::kPlannerError;
  if (no_path && back_off_if_stuck(request.start)) return;
  report_skipped(tour_->goal());
  ++tour_->next;
  ++tour_->skipped;
  ++stats_.goals_skipped;
  enter(tour_->done() ? State::kIdle : State::kToPlan);
  if (consecutive_failures_ >= config_.max_consecutive_failures || tour_->done())
    request_replan(ReplanReason::kInfeasible, 0,
                   std::to_string(consecutive_failures_) + " viewpoints without a path");
}

std::optional<msg::Waypoint> LowLevelPlanner::nudged_goal(const msg::Waypoint& goal) const {
  return recovery_.nudged_goal(goal,
                               [this](const msg::Waypoint& w) { return planner_->is_free(w); });
}

void LowLevelPlanner::send_backoff(const msg::Waypoint& start, const msg::Waypoint& escape) {
  if (auto loan = path_pub_.loan()) {
    (*loan)->plan_id = ++local_path_id_;
    (*loan)->waypoints = {start, escape};
    (void)path_pub_.publish(std::move(*loan));
  }
  local_path_ = {start, escape};
  backoff_ = Backoff{.escape = escape, .from = start.position};
  recovery_.reset_stall();
  enter(State::kBackingOff);
  mode_ = Mode::kMoving;
  send_maneuver(msg::Maneuver::Kind::kResume, {}, 0);
}

bool LowLevelPlanner::back_off_if_stuck(const msg::Waypoint& start) {
  const Eigen::Vector3d at = msg::to_eigen(start.position);
  const auto round = recovery_.count_no_path(at);
  if (!round) return false;
  // a round of failures from here: drop the roadmap (its validity marks and components
  // are what the failed queries grew) and leave, farther at each round
  planner_->clear_roadmap();
  if (round->from_m > config_.backoff_max_m + 1e-9) return false;
  const auto escape = escape_pose(start, round->from_m);
  if (!escape) return false;
  char what[160];
  std::snprintf(what, sizeof what,
                "%d queries without a path from (%.2f, %.2f, %.2f): backing off >= %.1f m "
                "(further such cases are counted)",
                config_.max_consecutive_failures, at.x(), at.y(), at.z(), round->from_m);
  log_once("stuck", what);
  send_backoff(start, *escape);
  ++stats_.stuck_backoffs;
  // the goal it could not reach stays the goal: planned again from the escape pose
  consecutive_failures_ = 0;
  return true;
}

std::optional<msg::Waypoint> LowLevelPlanner::escape_pose(const msg::Waypoint& start,
                                                          double from_m) const {
  // the map holds no teammate (their depth is masked): keep clear of them here
  const auto clear_of_teammates = [&](const msg::Waypoint& w) {
    for (const Teammate& t : teammates_) {
      if (!t.seen) continue;  // a lost one stands where it was last seen
      const double gap = traffic_radius_m_ + t.traffic_radius_m;
      if ((msg::to_eigen(w.position) - msg::to_eigen(t.state.T_world_body.position)).norm() < gap)
        return false;
    }
    return true;
  };
  return recovery_.escape_pose(
      start, from_m, checks_.obstacle.kind == RobotKind::kMultirotor,
      planner_->config().multirotor_max_altitude_m,
      [&](const msg::Waypoint& w) { return clear_of_teammates(w) && planner_->is_free(w); });
}

void LowLevelPlanner::watch_motion() {
  if (state_ == State::kBackingOff) {
    watch_backoff();
    return;
  }
  if (at_goal() || path_blocked() || obstacle_ahead()) return;
  mode_ = Mode::kMoving;
  watch_traffic();
}

void LowLevelPlanner::watch_backoff() {
  const Eigen::Vector3d position = msg::to_eigen(pose_->T_world_body.position);
  // the tracker stops at the escape pose (within its tolerance, 0.1 m); then the goal is
  // planned again from there. Reached: within GoalReached's tolerance (0.25 m), but closer
  // than 0.6 of the way for a short back-off: the escape pose backoff_min_m (0.2 m) away
  // lies within 0.25 m of the start, so it would count as reached before any motion, and
  // the robot would back off on the spot, tick after tick
  const Eigen::Vector3d escape = msg::to_eigen(backoff_->escape.position);
  const double way_m = (escape - msg::to_eigen(backoff_->from)).norm();
  if ((position - escape).norm() < std::min(checks_.goal.position_tolerance_m, 0.6 * way_m)) {
    backoff_.reset();
    enter(State::kToPlan);
  }
  mode_ = Mode::kMoving;
}

bool LowLevelPlanner::at_goal() {
  const Eigen::Vector3d position = msg::to_eigen(pose_->T_world_body.position);
  const double yaw = yaw_of(pose_->T_world_body.orientation);
  const msg::Waypoint& goal = tour_->goal();
  if (!goal_reached(checks_.obstacle.kind, position, yaw, msg::to_eigen(goal.position),
                    goal.yaw_rad, checks_.goal))
    return false;
  ++stats_.goals_reached;
  ++tour_->next;
  enter(tour_->done() ? State::kIdle : State::kToPlan);
  consecutive_failures_ = 0;
  if (pending_) {
    auto [sequence, id] = std::move(*pending_);
    take(sequence, id);
  }
  return true;
}

bool LowLevelPlanner::path_blocked() {
  if (!map_unchecked_ || config_.path_recheck_horizon_m <= 0) return false;
  map_unchecked_ = false;
  const PathRecheck r =
      recheck_path(local_path_, msg::to_eigen(pose_->T_world_body.position),
                   config_.path_recheck_horizon_m, config_.planner.collision_check_step_m,
                   [this](const msg::Waypoint& w) { return planner_->is_free(w); });
  if (!r.blocked) return false;
  ++stats_.paths_blocked;
  char what[160];
  std::snprintf(what, sizeof what,
                "a newer map blocks the local path %.2f m ahead, at (%.2f, %.2f, %.2f): "
                "planned again from here (further such cases are counted)",
                r.blocked_at_m, r.where.x(), r.where.y(), r.where.z());
  log_once("path_blocked", what);
  enter(State::kToPlan);  // the next tick plans to the same goal from the robot's pose
  return true;
}

bool LowLevelPlanner::obstacle_ahead() {
  if (!map_) return false;
  const Eigen::Vector3d position = msg::to_eigen(pose_->T_world_body.position);
  const double yaw = yaw_of(pose_->T_world_body.orientation);
  // only an obstacle ahead of the motion stops the robot: one behind or beside it that
  // the robot moves away from cannot be hit, and a stop there would never clear
  const Eigen::Vector3d ahead = checks_.obstacle.kind == RobotKind::kGround
                                    ? Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0)
                                    : msg::to_eigen(pose_->linear_velocity_mps).normalized();
  const ObstacleCheckResult o =
      obstacle_check(position, yaw, map_->voxel_m(), occupancy_query(map_), checks_.obstacle);
  const bool stop = o.stop() && ahead.allFinite() && ahead.dot(o.nearest_occupied - position) > 0;
  if (!stop) return false;
  ++stats_.emergency_stops;
  send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);
  mode_ = Mode::kStopped;
  request_replan(ReplanReason::kObstacle, 0, to_string(o.status));
  return true;
}

void LowLevelPlanner::watch_traffic() {
  if (!config_.traffic_policy || teammates_.empty()) return;
  const TrafficDecision d =
      traffic_decision(remaining_path(local_path_, msg::to_eigen(pose_->T_world_body.position)));
  switch (d.action) {
    case TrafficAction::kProceed:
      break;
    case TrafficAction::kStopAndWait:
      if (last_maneuver_ != msg::Maneuver::Kind::kStop) ++stats_.traffic_holds;
      send_maneuver(msg::Maneuver::Kind::kStop, {}, d.because_of_robot);
      mode_ = Mode::kWaiting;
      held_by_ = d.because_of_robot;
      break;
    case TrafficAction::kStepAside:
      if (last_maneuver_ != msg::Maneuver::Kind::kStepAside) {
        ++stats_.traffic_holds;
        aside_sent_ = AsideSent{.point = d.aside_point, .at_s = now_s()};
        send_maneuver(msg::Maneuver::Kind::kStepAside,
                      {.position = msg::to_msg(d.aside_point), .yaw_rad = d.aside_yaw_rad},
                      d.because_of_robot);
      }
      mode_ = Mode::kSteppingAside;
      held_by_ = d.because_of_robot;
      break;
    case TrafficAction::kResume:
      // back to the tour from where the robot now is: a new path to the goal
      send_maneuver(msg::Maneuver::Kind::kResume, {}, d.because_of_robot);
      enter(State::kToPlan);
      break;
  }
  if (d.request_replan) {
    // held by a lost teammate, which will never move: the goal behind it is out of reach
    const auto lost = std::find_if(teammates_.begin(), teammates_.end(), [&](const Teammate& t) {
      return t.id == d.because_of_robot && t.state.mode == Mode::kLost;
    });
    if (lost != teammates_.end()) {
      traffic_->reset();
      skip_goal("held by a lost teammate");  // stops the path that leads there
      return;
    }
    request_replan(ReplanReason::kTrafficStuck, d.because_of_robot,
                   "held " + std::to_string(static_cast<int>(d.held_s)) + " s");
  }
}

void LowLevelPlanner::watch_stall() {
  // only a robot that should be moving, on a pose it can trust: a hold, a stop, a reached
  // goal or a lost odometry (the tracker holds still, then may turn) restarts the watch
  if (mode_ != Mode::kMoving || !path_is_out() || !tour_ || tour_->done() ||
      pose_->tracking_quality <= 0) {
    recovery_.reset_stall();
    return;
  }
  const Eigen::Vector3d at = msg::to_eigen(pose_->T_world_body.position);
  const bool planar = checks_.obstacle.kind == RobotKind::kGround;
  if (!recovery_.stalled(remaining_length_m(local_path_, at, planar), now_s())) return;
  ++stats_.stalls;
  enter(State::kToPlan);  // the next tick plans to the goal from here
  backoff_.reset();
  // the first stall on this goal (here: within backoff_max_m of the last one) plans again;
  // the second skips the goal
  const bool again = recovery_.stalled_again(tour_->plan_id, tour_->next, at);
  const msg::Vec3& g = tour_->goal().position;
  char what[200];
  if (!again) {
    std::snprintf(what, sizeof what,
                  "no progress from (%.2f, %.2f, %.2f) for %.0f s on a path to (%.2f, %.2f, "
                  "%.2f): planned again from here (further such cases are counted)",
                  at.x(), at.y(), at.z(), config_.stall.timeout_s, g.x, g.y, g.z);
    log_once("stall", what);
    return;
  }
  std::snprintf(what, sizeof what,
                "no progress again on a path to (%.2f, %.2f, %.2f): that viewpoint is skipped "
                "(further such cases are counted)",
                g.x, g.y, g.z);
  log_once("stall_skip", what);
  skip_goal("no progress to the last goal");
}

bool LowLevelPlanner::over_detour_budget(double planned_m, double left_m) {
  const auto d = recovery_.over_detour_budget(tour_->plan_id, tour_->next, stats_.path_length_m,
                                              planned_m, left_m);
  if (!d) return false;
  const msg::Vec3& g = tour_->goal().position;
  char what[220];
  std::snprintf(what, sizeof what,
                "the way to (%.2f, %.2f, %.2f) grew to at least %.1f m (%.1f m travelled), "
                "over the detour budget %.1f m (first path %.1f m): that viewpoint is skipped "
                "(further such cases are counted)",
                g.x, g.y, g.z, d->way_m, d->travelled_m, d->budget_m, d->first_m);
  log_once("detour", what);
  return true;
}

void LowLevelPlanner::skip_goal(const char* why) {
  report_skipped(tour_->goal());
  ++tour_->next;
  ++tour_->skipped;
  ++stats_.goals_skipped;
  // a path still out leads to the skipped goal: stop it (the next path resumes)
  if (path_is_out()) send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);
  enter(tour_->done() ? State::kIdle : State::kToPlan);
  if (pending_) {  // held back until this goal was done: a skip is done with it
    auto [sequence, id] = std::move(*pending_);
    take(sequence, id);
    return;
  }
  if (tour_->done()) {
    send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);  // the old path leads to the skipped goal
    request_replan(ReplanReason::kInfeasible, 0, why);
  }
}

void LowLevelPlanner::report_skipped(const msg::Waypoint& goal) {
  if (auto loan = skipped_pub_.loan()) {
    msg::Odometry& o = **loan;
    o = msg::Odometry{};
    o.header.stamp_ns = clock().now_ns();
    o.T_world_body.position = goal.position;
    o.T_world_body.orientation = {
        .w = std::cos(goal.yaw_rad / 2), .x = 0, .y = 0, .z = std::sin(goal.yaw_rad / 2)};
    o.tracking_quality = 1.0;
    (void)skipped_pub_.publish(std::move(*loan));
  }
}

}  // namespace scancrew::low_level_planner
