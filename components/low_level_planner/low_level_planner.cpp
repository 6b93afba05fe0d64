#include "components/low_level_planner/low_level_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "components/low_level_planner/planner_params.hpp"
#include "core/motion/goal_check.hpp"
#include "core/motion/map_queries.hpp"
#include "core/motion/obstacle_check.hpp"
#include "core/motion/path_recheck.hpp"
#include "core/motion/redundancy_check.hpp"
#include "core/motion/utility_check.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::low_level_planner {

using motion::aside_on_the_way;
using motion::count_remaining;
using motion::first_waypoint_ahead;
using motion::free_space_query;
using motion::FreeSpaceSpec;
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

// slower than this, a teammate off kMoving is taken as holding its place (m/s)
constexpr double kMovingSpeedMps = 0.05;

bool finite(const msg::Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The rest of a local path for the traffic policy: the waypoints after the segment nearest
// to the robot (it is somewhere along that segment), goal last. Not from the nearest
// waypoint: on a long straight path that is the start, behind the robot, and the policy's
// path cut at the safety distance would then only hold the way back.
std::vector<Eigen::Vector3d> remaining_path(const std::vector<msg::Waypoint>& path,
                                            const Eigen::Vector3d& position) {
  std::vector<Eigen::Vector3d> rest;
  if (path.empty()) return rest;
  const size_t from = first_waypoint_ahead(path, position);
  rest.reserve(path.size() - from);
  for (size_t k = from; k < path.size(); ++k) rest.push_back(msg::to_eigen(path[k].position));
  return rest;
}

// The length of the path from `start` through its waypoints (m).
double path_length_m(const msg::Vec3& start, const std::vector<msg::Waypoint>& path) {
  double length = 0;
  Eigen::Vector3d at = msg::to_eigen(start);
  for (const msg::Waypoint& w : path) {
    const Eigen::Vector3d next = msg::to_eigen(w.position);
    length += (next - at).norm();
    at = next;
  }
  return length;
}

}  // namespace

LowLevelPlanner::Config LowLevelPlanner::read_config(ParamReader& p) {
  Config c;
  p.choice("pose_source", c.pose_source, {"ground_truth", "vio"});
  p.optional("control_period_s", c.control_period_s, {0.001, 10});
  p.optional("traffic_policy", c.traffic_policy);
  p.optional("redundancy_check", c.redundancy_check);
  p.optional("max_consecutive_failures", c.max_consecutive_failures, {1, 1000});
  p.optional("replan_timeout_s", c.replan_timeout_s, {0.1, 1e6});
  p.optional("backoff_max_m", c.backoff_max_m, {0, 100});
  p.optional("backoff_step_m", c.backoff_step_m, {0.01, 10});
  p.optional("backoff_min_m", c.backoff_min_m, {0.01, 100});
  p.optional("goal_nudge_max_m", c.goal_nudge_max_m, {0, 10});
  p.optional("stuck_backoff_m", c.stuck_backoff_m, {0, 100});
  p.optional("path_recheck_horizon_m", c.path_recheck_horizon_m, {0, 1000});
  p.optional("stall_timeout_s", c.stall.timeout_s, {0, 1e6});
  p.optional("stall_min_progress_m", c.stall.min_progress_m, {0.001, 100});
  p.optional("max_detour_factor", c.max_detour_factor, {0, 1000});
  if (c.max_detour_factor > 0 && c.max_detour_factor < 1)
    p.report("max_detour_factor", "must be 0 (off) or at least 1");
  if (c.backoff_min_m > c.backoff_max_m) p.report("backoff_min_m", "must not exceed backoff_max_m");
  p.optional("ground_nominal_speed_mps", c.ground_nominal_speed_mps, {0.01, 100});
  p.optional("multirotor_nominal_speed_mps", c.multirotor_nominal_speed_mps, {0.01, 100});
  p.optional("ground_traffic_radius_m", c.ground_traffic_radius_m, {0.01, 100});
  p.optional("multirotor_traffic_radius_m", c.multirotor_traffic_radius_m, {0.01, 100});
  c.planner = read_planner_config(p);
  c.ground_checks = read_checks_config(p, RobotKind::kGround);
  c.multirotor_checks = read_checks_config(p, RobotKind::kMultirotor);
  return c;
}

LowLevelPlanner::LowLevelPlanner(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)), stall_(config_.stall) {}

LowLevelPlanner::~LowLevelPlanner() = default;

Result<void, std::string> LowLevelPlanner::on_configure() {
  const auto self = std::find_if(team().begin(), team().end(),
                                 [&](const TeamMember& m) { return m.id == robot_id(); });
  if (self == team().end())
    return make_unexpected("the low-level planner runs per robot (per_robot: true)");
  const RobotKind kind = self->kind == "multirotor" ? RobotKind::kMultirotor : RobotKind::kGround;
  // the launch file's kind decides; robot_type only matters outside a launch file
  config_.planner.robot_kind = kind;
  const bool multirotor = kind == RobotKind::kMultirotor;
  checks_ = multirotor ? config_.multirotor_checks : config_.ground_checks;
  nominal_speed_mps_ =
      multirotor ? config_.multirotor_nominal_speed_mps : config_.ground_nominal_speed_mps;
  traffic_radius_m_ =
      multirotor ? config_.multirotor_traffic_radius_m : config_.ground_traffic_radius_m;
  if (std::string problem = checks_.validate(); !problem.empty()) return make_unexpected(problem);
  auto planner = MotionPlanner::create(config_.planner);
  if (!planner) return make_unexpected(planner.error());
  planner_.emplace(std::move(planner).value());
  traffic_.emplace(checks_.traffic);

  path_pub_ = create_publisher<msg::LocalPath>("local_path", {.pool_size = 2});
  maneuver_pub_ = create_publisher<msg::Maneuver>("maneuver", {.pool_size = 2});
  state_pub_ = create_publisher<msg::RobotState>("robot_state", {.pool_size = 4});
  tour_pub_ = create_publisher<msg::TeamPlan>("tour", {.pool_size = 2});
  skipped_pub_ = create_publisher<msg::Odometry>("skipped_goal", {.pool_size = 2});
  create_subscription<msg::TeamPlan>("plan", {.depth = 4},
                                     [this](Sample<msg::TeamPlan>&& s) { on_plan(*s); });
  create_subscription<msg::MapUpdate>("map", {.depth = 1}, [this](Sample<msg::MapUpdate>&& s) {
    if (s->map == nullptr) return;
    map_ = s->map;
    planner_->update_map(map_, s->header.stamp_ns);
    map_unchecked_ = true;
  });
  create_subscription<msg::IseSet>("ises", {.depth = 1}, [this](Sample<msg::IseSet>&& s) {
    const double voxel = map_ ? map_->voxel_m() : config_.planner.collision_check_step_m;
    current_ises_ = voxel_keys(s->centers_m, voxel);
    have_ises_ = true;
  });
  create_subscription<msg::Odometry>(config_.pose_source == "vio" ? "odom" : "pose_gt",
                                     {.depth = 1},
                                     [this](Sample<msg::Odometry>&& s) { on_pose(*s); });
  for (const TeamMember& m : team()) {
    if (m.id == robot_id()) continue;
    const size_t i = teammates_.size();
    const bool mate_multirotor = m.kind == "multirotor";
    teammates_.push_back({.id = m.id,
                          .nominal_speed_mps = mate_multirotor
                                                   ? config_.multirotor_nominal_speed_mps
                                                   : config_.ground_nominal_speed_mps,
                          .traffic_radius_m = mate_multirotor ? config_.multirotor_traffic_radius_m
                                                              : config_.ground_traffic_radius_m});
    const std::string ns = "/" + m.ns + "/";
    create_subscription<msg::RobotState>(ns + "robot_state", {.depth = 1},
                                         [this, i](Sample<msg::RobotState>&& s) {
                                           Teammate& t = teammates_[i];
                                           // the bridge's kLost (a dead process) carries no
                                           // pose: the body stays where it was last seen
                                           // (a teammate never seen stays unseen: the
                                           // message's pose is no place)
                                           if (s->mode == Mode::kLost) {
                                             t.state.mode = Mode::kLost;
                                             t.state.velocity_mps = {};
                                           } else {
                                             t.state = *s;
                                             t.seen = true;
                                           }
                                           park_lost_teammates();
                                         });
    create_subscription<msg::LocalPath>(
        ns + "local_path", {.depth = 1},
        [this, i](Sample<msg::LocalPath>&& s) { teammates_[i].local_path = s->waypoints; });
    create_subscription<msg::TeamPlan>(ns + "tour", {.depth = 1},
                                       [this, i](Sample<msg::TeamPlan>&& s) {
                                         if (s->sequences.empty()) return;
                                         teammates_[i].tour = s->sequences.front();
                                         teammates_[i].tour_plan_id = s->plan_id;
                                       });
  }
  create_timer(std::chrono::nanoseconds(static_cast<int64_t>(config_.control_period_s * 1e9)),
               [this] { tick(); });
  return {};
}

void LowLevelPlanner::on_plan(const msg::TeamPlan& plan) {
  const auto mine =
      std::find_if(plan.sequences.begin(), plan.sequences.end(),
                   [&](const msg::PathSequence& s) { return s.robot_id == robot_id(); });
  if (mine == plan.sequences.end() || plan.plan_id <= last_plan_id_) return;
  last_plan_id_ = plan.plan_id;
  const bool awaited = awaiting_after_ && plan.plan_id > *awaiting_after_;
  // an empty sequence for a robot with nothing to do changes nothing: not a tour (a
  // centralized planner publishes at every cluster update, and each counted as a tour of
  // every idle robot: 12-33 tours per goal in Step 10's centralized teams)
  if (!awaited && mine->viewpoints.empty() && (!tour_ || tour_->done())) return;
  if (!tour_ || tour_->done() || awaited)
    take(*mine, plan.plan_id);
  else
    pending_.emplace(*mine, plan.plan_id);  // on hold until the current goal is reached
}

void LowLevelPlanner::on_pose(const msg::Odometry& odom) {
  const msg::Vec3& p = odom.T_world_body.position;
  if (!finite(p)) {
    log_once("pose", "a non-finite pose (ignored)");
    return;
  }
  if (last_position_)
    stats_.path_length_m +=
        std::hypot(p.x - last_position_->x, p.y - last_position_->y, p.z - last_position_->z);
  last_position_ = p;
  pose_ = odom;
}

double LowLevelPlanner::now_s() {
  return static_cast<double>(clock().now_ns()) * 1e-9;
}

void LowLevelPlanner::take(const msg::PathSequence& sequence, uint64_t plan_id) {
  const double voxel = map_ ? map_->voxel_m() : config_.planner.collision_check_step_m;
  tour_ = make_tour(plan_id, sequence, voxel);
  pending_.reset();
  awaiting_after_.reset();
  // an empty tour: the path the tracker may still follow leads nowhere now
  if (sequence.viewpoints.empty() && path_sent_) send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);
  path_sent_ = false;
  backing_off_.reset();
  consecutive_failures_ = 0;
  traffic_->reset();
  ++stats_.tours;
  if (auto loan = tour_pub_.loan()) {
    msg::TeamPlan& m = **loan;
    m.plan_id = plan_id;
    m.sequences.assign(1, sequence);
    m.unassigned.clear();
    (void)tour_pub_.publish(std::move(*loan));
  }
}

void LowLevelPlanner::request_replan(ReplanReason reason, uint32_t because_of,
                                     const std::string& detail) {
  if (awaiting_after_) return;
  awaiting_after_ = last_plan_id_;
  awaiting_since_s_ = now_s();
  pending_.reset();  // computed before the reason to replan
  ++stats_.replans;
  mode_ = Mode::kPlanning;
  SCANCREW_LOG_DEBUG("%s: asks for a new plan: %s%s%s", qualified_name().c_str(), to_string(reason),
                     detail.empty() ? "" : ": ", detail.c_str());
  (void)because_of;
}

void LowLevelPlanner::send_maneuver(msg::Maneuver::Kind kind, const msg::Waypoint& aside,
                                    uint32_t because) {
  if (kind == last_maneuver_ && kind != msg::Maneuver::Kind::kStepAside) return;
  last_maneuver_ = kind;
  if (auto loan = maneuver_pub_.loan()) {
    (*loan)->kind = kind;
    (*loan)->aside = aside;
    (*loan)->because_of_robot = because;
    (void)maneuver_pub_.publish(std::move(*loan));
  }
}

void LowLevelPlanner::tick() {
  if (!pose_) return;
  held_by_ = 0;  // set again below while the traffic policy holds the robot
  if (awaiting_after_ && now_s() - awaiting_since_s_ > config_.replan_timeout_s) {
    // unanswered: the high-level planner acts on a change of mode, so pass through kWaiting
    awaiting_since_s_ = now_s();
    mode_ = Mode::kWaiting;
    publish_state();
    mode_ = Mode::kPlanning;
    publish_state();
    return;
  }
  if (awaiting_after_) {
    mode_ = Mode::kPlanning;
  } else if (!tour_ || tour_->done()) {
    mode_ = Mode::kIdle;  // the high-level planner reallocates to an idle robot
    make_way();
  } else if (!path_sent_) {
    if (!follow_checks()) plan_to_goal();
  } else {
    watch_motion();
    watch_stall();
  }
  publish_state();
}

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
      if (over_detour_budget(
              path_length_m(request.start.position, r.path),
              (msg::to_eigen(request.goal.position) - msg::to_eigen(request.start.position))
                  .norm())) {
        ++stats_.detours;
        send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);  // an old path may lead to it
        skip_goal("detour");
        return;
      }
      if (auto loan = path_pub_.loan()) {
        (*loan)->plan_id = ++local_path_id_;
        (*loan)->waypoints = r.path;
        (void)path_pub_.publish(std::move(*loan));
      }
      local_path_ = r.path;
      stuck_.reset();
      stall_.reset();
      ++stats_.paths;
      path_sent_ = true;
      map_unchecked_ = false;  // planned on the newest snapshot
      stopped_ = false;
      consecutive_failures_ = 0;
      mode_ = Mode::kMoving;
      send_maneuver(msg::Maneuver::Kind::kResume, {}, 0);
      return;
    case PlanStatus::kMapStale:
      mode_ = Mode::kWaiting;  // the next snapshot answers it
      log_once("stale", r.message + " (waiting for a newer map)");
      return;
    default:
      break;
  }
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
  if (r.status == PlanStatus::kNoPath && back_off_if_stuck(request.start)) return;
  report_skipped(tour_->goal());
  ++tour_->next;
  ++tour_->skipped;
  ++stats_.goals_skipped;
  if (consecutive_failures_ >= config_.max_consecutive_failures || tour_->done())
    request_replan(ReplanReason::kInfeasible, 0,
                   std::to_string(consecutive_failures_) + " viewpoints without a path");
}

// A lost teammate never moves again: the planner keeps the body clear of it, so that a
// path is planned round it (the traffic policy would hold the robot behind it for good;
// the split arena team ran out of time with robot 1 held 1.1 m behind killed robot 3).
void LowLevelPlanner::park_lost_teammates() {
  if (!planner_) return;
  std::vector<Eigen::Vector3d> centers;
  double radius = 0;
  for (const Teammate& t : teammates_)
    if (t.seen && t.state.mode == Mode::kLost) {
      centers.push_back(msg::to_eigen(t.state.T_world_body.position));
      radius = std::max(radius, t.traffic_radius_m);
    }
  planner_->set_parked(std::move(centers), radius);
}

std::optional<msg::Waypoint> LowLevelPlanner::nudged_goal(const msg::Waypoint& goal) const {
  constexpr int kDirections = 16;
  for (double r = config_.backoff_step_m; r <= config_.goal_nudge_max_m + 1e-9;
       r += config_.backoff_step_m)
    for (int k = 0; k < kDirections; ++k) {
      const double angle = 2 * M_PI * k / kDirections;
      msg::Waypoint w = goal;
      w.position.x += r * std::cos(angle);
      w.position.y += r * std::sin(angle);
      if (planner_->is_free(w)) return w;
    }
  return std::nullopt;
}

void LowLevelPlanner::send_backoff(const msg::Waypoint& start, const msg::Waypoint& escape) {
  if (auto loan = path_pub_.loan()) {
    (*loan)->plan_id = ++local_path_id_;
    (*loan)->waypoints = {start, escape};
    (void)path_pub_.publish(std::move(*loan));
  }
  local_path_ = {start, escape};
  backing_off_ = escape;
  backoff_start_ = start.position;
  stall_.reset();
  path_sent_ = true;
  stopped_ = false;
  mode_ = Mode::kMoving;
  send_maneuver(msg::Maneuver::Kind::kResume, {}, 0);
}

bool LowLevelPlanner::back_off_if_stuck(const msg::Waypoint& start) {
  if (config_.stuck_backoff_m <= 0) return false;
  const Eigen::Vector3d at = msg::to_eigen(start.position);
  // one place: within backoff_max_m of the first failure (each round backs off farther)
  if (!stuck_ || (at - stuck_->at).norm() > config_.backoff_max_m) stuck_ = StuckSpot{.at = at};
  if (++stuck_->failures < config_.max_consecutive_failures) return false;
  // a round of failures from here: drop the roadmap (its validity marks and components
  // are what the failed queries grew) and leave, farther at each round
  stuck_->failures = 0;
  ++stuck_->rounds;
  planner_->clear_roadmap();
  const double from_m = config_.stuck_backoff_m * stuck_->rounds;
  if (from_m > config_.backoff_max_m + 1e-9) return false;
  const auto escape = escape_pose(start, from_m);
  if (!escape) return false;
  char what[160];
  std::snprintf(what, sizeof what,
                "%d queries without a path from (%.2f, %.2f, %.2f): backing off >= %.1f m "
                "(further such cases are counted)",
                config_.max_consecutive_failures, at.x(), at.y(), at.z(), from_m);
  log_once("stuck", what);
  send_backoff(start, *escape);
  ++stats_.stuck_backoffs;
  // the goal it could not reach stays the goal: planned again from the escape pose
  consecutive_failures_ = 0;
  return true;
}

std::optional<msg::Waypoint> LowLevelPlanner::escape_pose(const msg::Waypoint& start,
                                                          double from_m) const {
  constexpr int kDirections = 16;
  const bool multirotor = checks_.obstacle.kind == RobotKind::kMultirotor;
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
  const auto free = [&](const msg::Waypoint& w) {
    return clear_of_teammates(w) && planner_->is_free(w);
  };
  // from backoff_min_m: an escape pose within the tracker's position tolerance would be
  // "reached" without a move, and the robot would back off on the spot forever
  for (double r = from_m; r <= config_.backoff_max_m + 1e-9; r += config_.backoff_step_m) {
    if (multirotor) {
      msg::Waypoint up = start;
      up.position.z += r;
      // not above the altitude band: from there no query has a valid start (a UAV of an
      // outdoor trio backed off to 44.8 m, over 40, and never planned again)
      if (up.position.z <= planner_->config().multirotor_max_altitude_m && free(up)) return up;
    }
    for (int k = 0; k < kDirections; ++k) {
      // behind first: the robot stopped facing what it must not hit
      const double angle =
          start.yaw_rad + M_PI + 2 * M_PI * (k % 2 == 0 ? k / 2 : -(k + 1) / 2) / kDirections;
      msg::Waypoint w = start;
      w.position.x += r * std::cos(angle);
      w.position.y += r * std::sin(angle);
      if (free(w)) return w;
    }
  }
  return std::nullopt;
}

TrafficAgent LowLevelPlanner::self_agent() const {
  TrafficAgent a;
  a.id = robot_id();
  a.position = msg::to_eigen(pose_->T_world_body.position);
  a.yaw_rad = yaw_of(pose_->T_world_body.orientation);
  a.velocity_mps = msg::to_eigen(pose_->linear_velocity_mps);
  a.nominal_speed_mps = nominal_speed_mps_;
  a.body_radius_m = traffic_radius_m_;
  return a;
}

void LowLevelPlanner::watch_motion() {
  const Eigen::Vector3d position = msg::to_eigen(pose_->T_world_body.position);
  const double yaw = yaw_of(pose_->T_world_body.orientation);
  if (backing_off_) {
    // the tracker stops at the escape pose (within its tolerance, 0.1 m); then the goal is
    // planned again from there. Reached: within GoalReached's tolerance (0.25 m), but closer
    // than 0.6 of the way for a short back-off: the escape pose backoff_min_m (0.2 m) away
    // lies within 0.25 m of the start, so it would count as reached before any motion, and
    // the robot would back off on the spot, tick after tick
    const Eigen::Vector3d escape = msg::to_eigen(backing_off_->position);
    const double way_m = (escape - msg::to_eigen(backoff_start_)).norm();
    if ((position - escape).norm() < std::min(checks_.goal.position_tolerance_m, 0.6 * way_m)) {
      backing_off_.reset();
      path_sent_ = false;
    }
    mode_ = Mode::kMoving;
    return;
  }
  const msg::Waypoint& goal = tour_->goal();
  if (goal_reached(checks_.obstacle.kind, position, yaw, msg::to_eigen(goal.position), goal.yaw_rad,
                   checks_.goal)) {
    ++stats_.goals_reached;
    ++tour_->next;
    path_sent_ = false;
    consecutive_failures_ = 0;
    if (pending_) {
      auto [sequence, id] = std::move(*pending_);
      take(sequence, id);
    }
    return;
  }
  if (map_unchecked_ && !stopped_ && config_.path_recheck_horizon_m > 0) {
    map_unchecked_ = false;
    const PathRecheck r =
        recheck_path(local_path_, position, config_.path_recheck_horizon_m,
                     config_.planner.collision_check_step_m,
                     [this](const msg::Waypoint& w) { return planner_->is_free(w); });
    if (r.blocked) {
      ++stats_.paths_blocked;
      char what[160];
      std::snprintf(what, sizeof what,
                    "a newer map blocks the local path %.2f m ahead, at (%.2f, %.2f, %.2f): "
                    "planned again from here (further such cases are counted)",
                    r.blocked_at_m, r.where.x(), r.where.y(), r.where.z());
      log_once("path_blocked", what);
      path_sent_ = false;  // the next tick plans to the same goal from the robot's pose
      return;
    }
  }
  if (map_ && !stopped_) {
    // only an obstacle ahead of the motion stops the robot: one behind or beside it that
    // the robot moves away from cannot be hit, and a stop there would never clear
    const Eigen::Vector3d ahead = checks_.obstacle.kind == RobotKind::kGround
                                      ? Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0)
                                      : msg::to_eigen(pose_->linear_velocity_mps).normalized();
    const ObstacleCheckResult o =
        obstacle_check(position, yaw, map_->voxel_m(), occupancy_query(map_), checks_.obstacle);
    if (o.stop() && ahead.allFinite() && ahead.dot(o.nearest_occupied - position) > 0) {
      stopped_ = true;
      ++stats_.emergency_stops;
      send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);
      mode_ = Mode::kStopped;
      request_replan(ReplanReason::kObstacle, 0, to_string(o.status));
      return;
    }
  }
  mode_ = Mode::kMoving;
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
      path_sent_ = false;
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
  if (mode_ != Mode::kMoving || stopped_ || !path_sent_ || !tour_ || tour_->done() ||
      pose_->tracking_quality <= 0) {
    stall_.reset();
    return;
  }
  const Eigen::Vector3d at = msg::to_eigen(pose_->T_world_body.position);
  const bool planar = checks_.obstacle.kind == RobotKind::kGround;
  if (!stall_.update(remaining_length_m(local_path_, at, planar), now_s())) return;
  ++stats_.stalls;
  path_sent_ = false;  // the next tick plans to the goal from here
  backing_off_.reset();
  // the first stall on this goal (here: within backoff_max_m of the last one) plans again;
  // the second skips the goal
  const bool again = stall_goal_ && stall_goal_->plan_id == tour_->plan_id &&
                     stall_goal_->goal == tour_->next &&
                     (at - stall_goal_->at).norm() <= config_.backoff_max_m;
  const msg::Vec3& g = tour_->goal().position;
  char what[200];
  if (!again) {
    stall_goal_ = StallGoal{.plan_id = tour_->plan_id, .goal = tour_->next, .at = at};
    std::snprintf(what, sizeof what,
                  "no progress from (%.2f, %.2f, %.2f) for %.0f s on a path to (%.2f, %.2f, "
                  "%.2f): planned again from here (further such cases are counted)",
                  at.x(), at.y(), at.z(), config_.stall.timeout_s, g.x, g.y, g.z);
    log_once("stall", what);
    return;
  }
  stall_goal_.reset();
  std::snprintf(what, sizeof what,
                "no progress again on a path to (%.2f, %.2f, %.2f): that viewpoint is skipped "
                "(further such cases are counted)",
                g.x, g.y, g.z);
  log_once("stall_skip", what);
  skip_goal("no progress to the last goal");
}

bool LowLevelPlanner::over_detour_budget(double planned_m, double left_m) {
  if (config_.max_detour_factor <= 0) return false;
  if (!goal_cost_ || goal_cost_->plan_id != tour_->plan_id || goal_cost_->goal != tour_->next) {
    goal_cost_ = GoalCost{.plan_id = tour_->plan_id,
                          .goal = tour_->next,
                          .travelled_at_m = stats_.path_length_m,
                          .first_m = planned_m};
    return false;
  }
  const double way_m = stats_.path_length_m - goal_cost_->travelled_at_m + left_m;
  const double budget_m =
      config_.max_detour_factor * goal_cost_->first_m + config_.path_recheck_horizon_m;
  if (way_m <= budget_m) return false;
  const msg::Vec3& g = tour_->goal().position;
  char what[220];
  std::snprintf(what, sizeof what,
                "the way to (%.2f, %.2f, %.2f) grew to at least %.1f m (%.1f m travelled), "
                "over the detour budget %.1f m (first path %.1f m): that viewpoint is skipped "
                "(further such cases are counted)",
                g.x, g.y, g.z, way_m, stats_.path_length_m - goal_cost_->travelled_at_m, budget_m,
                goal_cost_->first_m);
  log_once("detour", what);
  return true;
}

void LowLevelPlanner::skip_goal(const char* why) {
  report_skipped(tour_->goal());
  ++tour_->next;
  ++tour_->skipped;
  ++stats_.goals_skipped;
  // a path still out leads to the skipped goal: stop it (the next path resumes)
  if (path_sent_) send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);
  path_sent_ = false;
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

// The traffic policy's decision for this robot on `path` (its remaining local path; empty
// for a robot holding its place) against every teammate's broadcast state.
TrafficDecision LowLevelPlanner::traffic_decision(std::vector<Eigen::Vector3d> path) {
  std::vector<TrafficAgent> others;
  for (const Teammate& t : teammates_) {
    // a lost teammate is still there (a dead process leaves its robot where it stood, and
    // the depth mask blanked it out of the maps until then): it holds its place
    if (!t.seen) continue;
    TrafficAgent a;
    a.id = t.id;
    a.position = msg::to_eigen(t.state.T_world_body.position);
    a.yaw_rad = yaw_of(t.state.T_world_body.orientation);
    a.velocity_mps = msg::to_eigen(t.state.velocity_mps);
    a.nominal_speed_mps = t.nominal_speed_mps;
    a.body_radius_m = t.traffic_radius_m;
    // a teammate still on its last path (it may be waiting for a plan, or held by the
    // traffic policy, meanwhile) has the rest of it ahead; one at rest off a path holds its
    // place. (A held teammate read as parked made a deadlock: it waited for an idle robot in
    // its way, which saw two parked robots and nothing to negotiate.)
    const bool moving = t.state.mode == Mode::kMoving || t.state.mode == Mode::kWaiting ||
                        a.velocity_mps.norm() > kMovingSpeedMps;
    if (moving) a.path = remaining_path(t.local_path, a.position);
    others.push_back(std::move(a));
  }
  TrafficAgent me = self_agent();
  me.path = std::move(path);  // empty: the robot reads as holding its place
  FreeSpaceSpec spec;
  spec.kind = checks_.obstacle.kind;
  spec.body_radius_m = me.body_radius_m;
  spec.min_height_m = checks_.obstacle.min_height_m;
  spec.max_height_m = checks_.obstacle.max_height_m;
  const FreeSpaceQuery free = map_ ? free_space_query(map_, spec) : FreeSpaceQuery{};
  TrafficDecision d = traffic_->update(me, others, free, now_s());
  log_traffic(d);
  return d;
}

void LowLevelPlanner::log_traffic(const TrafficDecision& d) {
  if (log::threshold() < log::Level::kDebug) return;
  const bool new_aside = d.action == TrafficAction::kStepAside &&
                         (d.aside_point - last_traffic_.aside_point).norm() > 0.05;
  if (d.action == last_traffic_.action && d.encounter == last_traffic_.encounter &&
      d.because_of_robot == last_traffic_.because_of_robot && !new_aside)
    return;
  last_traffic_ = d;
  const msg::Vec3& p = pose_->T_world_body.position;
  std::string mates;
  for (const Teammate& t : teammates_) {
    if (!t.seen) continue;
    const msg::Vec3& q = t.state.T_world_body.position;
    char buf[96];
    std::snprintf(buf, sizeof buf, " r%u %s at (%.2f, %.2f) %.2f m", t.id,
                  msg::to_string(t.state.mode), q.x, q.y, std::hypot(q.x - p.x, q.y - p.y));
    mates += buf;
  }
  char to[48] = "";
  if (d.action == TrafficAction::kStepAside)
    std::snprintf(to, sizeof to, " to (%.2f, %.2f)", d.aside_point.x(), d.aside_point.y());
  SCANCREW_LOG_DEBUG(
      "%s: t %.1f s traffic %s%s%s (%s, robot %u, held %.1f s) at (%.2f, %.2f), mode %s;%s",
      qualified_name().c_str(), now_s(), to_string(d.action), to,
      d.no_aside_point ? " (no aside point)" : "", to_string(d.encounter), d.because_of_robot,
      d.held_s, p.x, p.y, msg::to_string(mode_), mates.c_str());
}

// An idle robot holds its place; when it blocks a teammate's way (traffic rule "blocking":
// the holding robot steps aside, docs/traffic_policy.md) it steps aside and stays at the
// aside point until its next path (plan_to_goal's kResume): a resume as soon as the policy
// sees the way clear stopped it half-way, back within the teammate's clearance. Before this,
// only a moving robot ran the policy, and a teammate whose goal lay past an idle robot
// waited for it for ever (the parking lot's 3-robot centralized team, seed 2).
// Once there (within GoalReached's tolerance, or after max_wait_s on the way), it looks
// again: a teammate whose path has changed since may still find it in the way (the parking
// lot's distributed pair: robot 2 held for 300 s beside robot 1 at its first aside point).
void LowLevelPlanner::make_way() {
  if (!config_.traffic_policy || teammates_.empty() || !map_) return;
  if (last_maneuver_ == msg::Maneuver::Kind::kStepAside) {
    if (!aside_sent_) return;
    if (aside_on_the_way(checks_.obstacle.kind, msg::to_eigen(pose_->T_world_body.position),
                         aside_sent_->point, now_s() - aside_sent_->at_s, checks_.goal,
                         checks_.traffic.max_wait_s))
      return;           // on the way
    traffic_->reset();  // from here, a new aside point if still in the way
  }
  const TrafficDecision d = traffic_decision({});
  if (d.action != TrafficAction::kStepAside) return;
  ++stats_.traffic_holds;
  aside_sent_ = AsideSent{.point = d.aside_point, .at_s = now_s()};
  send_maneuver(msg::Maneuver::Kind::kStepAside,
                {.position = msg::to_msg(d.aside_point), .yaw_rad = d.aside_yaw_rad},
                d.because_of_robot);
}

void LowLevelPlanner::publish_state() {
  auto loan = state_pub_.loan();
  if (!loan) return;
  msg::RobotState& s = **loan;
  s.T_world_body = pose_->T_world_body;
  s.velocity_mps = pose_->linear_velocity_mps;
  s.mode = mode_;
  s.plan_id = tour_ ? tour_->plan_id : 0;
  s.current_cluster = tour_ && !tour_->done() ? tour_->goal_cluster() : 0;
  s.path_index = tour_ ? static_cast<uint32_t>(tour_->next) : 0;
  s.steps_remaining = tour_ ? static_cast<uint32_t>(tour_->remaining()) : 0;
  s.path_length_m = stats_.path_length_m;
  s.backing_off = backing_off_.has_value();
  s.held_by_robot = mode_ == Mode::kWaiting || mode_ == Mode::kSteppingAside ? held_by_ : 0;
  (void)state_pub_.publish(std::move(*loan));
}

void LowLevelPlanner::log_once(const std::string& key, const std::string& message) {
  if (std::find(logged_.begin(), logged_.end(), key) != logged_.end()) return;
  logged_.push_back(key);
  SCANCREW_LOG_WARN("%s: %s", qualified_name().c_str(), message.c_str());
}

void LowLevelPlanner::on_deactivate() {
  SCANCREW_LOG_INFO(
      "%s: %llu tours, %llu goals reached, %llu skipped, %llu paths (%.1f ms mean, %.1f max: "
      "LazyPRM* %.1f ms in %zu searches%s, shortcutting %.1f ms), "
      "%llu replanning requests, %llu emergency stops, %llu back-offs, %llu traffic holds, %llu "
      "redundancies, %.1f m travelled, %llu goals nudged, %llu paths blocked by a newer map, "
      "%llu back-offs from a place with no path out, %llu stalls, %llu goals over the detour "
      "budget",
      qualified_name().c_str(), static_cast<unsigned long long>(stats_.tours),
      static_cast<unsigned long long>(stats_.goals_reached),
      static_cast<unsigned long long>(stats_.goals_skipped),
      static_cast<unsigned long long>(stats_.paths),
      stats_.paths + stats_.plan_failures > 0
          ? stats_.plan_ms_sum / static_cast<double>(stats_.paths + stats_.plan_failures)
          : 0.0,
      stats_.plan_ms_max, stats_.slowest_plan.solve_ms, stats_.slowest_plan.searches,
      stats_.slowest_plan.search_cut ? " cut by the time limit" : "",
      stats_.slowest_plan.simplify_ms, static_cast<unsigned long long>(stats_.replans),
      static_cast<unsigned long long>(stats_.emergency_stops),
      static_cast<unsigned long long>(stats_.backoffs),
      static_cast<unsigned long long>(stats_.traffic_holds),
      static_cast<unsigned long long>(stats_.redundancies), stats_.path_length_m,
      static_cast<unsigned long long>(stats_.goals_nudged),
      static_cast<unsigned long long>(stats_.paths_blocked),
      static_cast<unsigned long long>(stats_.stuck_backoffs),
      static_cast<unsigned long long>(stats_.stalls),
      static_cast<unsigned long long>(stats_.detours));
}

SCANCREW_REGISTER_COMPONENT(LowLevelPlanner, "low_level_planner")

}  // namespace scancrew::low_level_planner
