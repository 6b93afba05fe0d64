#include "components/low_level_planner/low_level_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "components/low_level_planner/planner_params.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::low_level_planner {

namespace {

using Mode = msg::RobotState::Mode;

bool finite(const msg::Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

LowLevelPlanner::Config LowLevelPlanner::read_config(ParamReader& p) {
  Config c;
  p.optional("control_period_s", c.control_period_s, {0.001, 10})
      .doc("period of the checks while moving (GoalReached, ObstacleCheck, TrafficPolicy; s)");
  p.optional("traffic_policy", c.traffic_policy)
      .doc("apply the traffic policy between teammates (docs/traffic_policy.md)");
  p.optional("redundancy_check", c.redundancy_check)
      .doc("RedundancyCheck against teammates' tours (distributed teams, Algorithm 6)");
  p.optional("max_consecutive_failures", c.max_consecutive_failures, {1, 1000})
      .doc("queries in a row without a path before the robot asks for a new plan");
  p.optional("replan_timeout_s", c.replan_timeout_s, {0.1, 1e6})
      .doc("a replanning request unanswered this long is sent again, marked repeated (s)");
  p.optional("backoff_max_m", c.backoff_max_m, {0, 100})
      .doc("a start in collision: back off to the nearest free pose within this (m)");
  p.optional("backoff_step_m", c.backoff_step_m, {0.01, 10})
      .doc("back-off rings this far apart (m)");
  p.optional("backoff_min_m", c.backoff_min_m, {0.01, 100})
      .doc("the nearest back-off ring (m; above the tracker's 0.1 m position tolerance)");
  p.optional("goal_nudge_max_m", c.goal_nudge_max_m, {0, 10})
      .doc(
          "a goal in collision moves to the nearest free pose (same yaw) within this before it is "
          "skipped (m; 0: skip at once)");
  p.optional("stuck_backoff_m", c.stuck_backoff_m, {0, 100})
      .doc(
          "after max_consecutive_failures failures from one place: drop the roadmap and back off "
          "this much per round (m; 0: never)");
  p.optional("path_recheck_horizon_m", c.path_recheck_horizon_m, {0, 1000})
      .doc("at each new map, the path ahead is checked again out to this arc length (m; 0: never)");
  p.optional("stall_timeout_s", c.stall.timeout_s, {0, 1e6})
      .doc(
          "a robot whose way left has not shrunk by stall_min_progress_m for this long plans again "
          "(s; 0: never)");
  p.optional("stall_min_progress_m", c.stall.min_progress_m, {0.001, 100})
      .doc("the progress that ends a stall (m)");
  p.optional("max_detour_factor", c.max_detour_factor, {0, 1000})
      .doc(
          "a goal whose way grows past this × its first path (+ path_recheck_horizon_m) is skipped "
          "(0: never)");
  if (c.max_detour_factor > 0 && c.max_detour_factor < 1)
    p.report("max_detour_factor", "must be 0 (off) or at least 1");
  if (c.backoff_min_m > c.backoff_max_m) p.report("backoff_min_m", "must not exceed backoff_max_m");
  p.optional("ground_nominal_speed_mps", c.ground_nominal_speed_mps, {0.01, 100})
      .doc("the traffic policy's nominal speed of ground robots (m/s; table 5.3)");
  p.optional("multirotor_nominal_speed_mps", c.multirotor_nominal_speed_mps, {0.01, 100})
      .doc("the traffic policy's nominal speed of multirotors (m/s; 2.6.1)");
  p.optional("ground_traffic_radius_m", c.ground_traffic_radius_m, {0.01, 100})
      .doc("the traffic policy's radius holding a ground robot's body (m)");
  p.optional("multirotor_traffic_radius_m", c.multirotor_traffic_radius_m, {0.01, 100})
      .doc("the traffic policy's radius holding a multirotor's body, rotors included (m)");
  c.planner = read_planner_config(p);
  c.ground_checks = read_checks_config(p, RobotKind::kGround);
  c.multirotor_checks = read_checks_config(p, RobotKind::kMultirotor);
  return c;
}

LowLevelPlanner::LowLevelPlanner(ComponentContext context, Config config)
    : Component(std::move(context)),
      config_(std::move(config)),
      recovery_(RecoveryConfig{.max_consecutive_failures = config_.max_consecutive_failures,
                               .backoff_max_m = config_.backoff_max_m,
                               .backoff_step_m = config_.backoff_step_m,
                               .backoff_min_m = config_.backoff_min_m,
                               .goal_nudge_max_m = config_.goal_nudge_max_m,
                               .stuck_backoff_m = config_.stuck_backoff_m,
                               .max_detour_factor = config_.max_detour_factor,
                               .path_recheck_horizon_m = config_.path_recheck_horizon_m,
                               .stall = config_.stall}) {}

LowLevelPlanner::~LowLevelPlanner() = default;

Result<void, std::string> LowLevelPlanner::on_configure() {
  if (auto planner = configure_planner(); !planner) return planner;
  create_ports();
  subscribe_teammates();
  create_timer(std::chrono::nanoseconds(static_cast<int64_t>(config_.control_period_s * 1e9)),
               [this] { tick(); });
  return {};
}

// The robot's kind from the launch file: its checks, speed, traffic radius and motion planner.
Result<void, std::string> LowLevelPlanner::configure_planner() {
  const auto self = std::find_if(team().begin(), team().end(),
                                 [&](const TeamMember& m) { return m.id == robot_id(); });
  if (self == team().end())
    return make_unexpected("the low-level planner runs per robot (per_robot: true)");
  const RobotKind kind = self->kind;
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
  return {};
}

// The robot's own publishers and its subscriptions to plans, the map, ISEs and its pose.
void LowLevelPlanner::create_ports() {
  path_pub_ = create_publisher<msg::LocalPath>("local_path", {.pool_size = 2});
  maneuver_pub_ = create_publisher<msg::Maneuver>("maneuver", {.pool_size = 2});
  state_pub_ = create_publisher<msg::RobotState>("robot_state", {.pool_size = 4});
  // the tour is for teammates (their redundancy check): a robot alone has no reader
  if (team().size() > 1) tour_pub_ = create_publisher<msg::TeamPlan>("tour", {.pool_size = 2});
  skipped_pub_ = create_publisher<msg::Odometry>("skipped_goal", {.pool_size = 2});
  request_pub_ = create_publisher<msg::ReplanRequest>("replan_request", {.pool_size = 2});
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
  create_subscription<msg::Odometry>("pose", {.depth = 1},
                                     [this](Sample<msg::Odometry>&& s) { on_pose(*s); });
}

// Subscribes to each teammate's state, local path and tour.
void LowLevelPlanner::subscribe_teammates() {
  for (const TeamMember& m : team()) {
    if (m.id == robot_id()) continue;
    const size_t i = teammates_.size();
    const bool mate_multirotor = m.kind == RobotKind::kMultirotor;
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
}

void LowLevelPlanner::on_plan(const msg::TeamPlan& plan) {
  const auto mine =
      std::find_if(plan.sequences.begin(), plan.sequences.end(),
                   [&](const msg::PathSequence& s) { return s.robot_id == robot_id(); });
  if (mine == plan.sequences.end() || plan.plan_id <= last_plan_id_) return;
  last_plan_id_ = plan.plan_id;
  const bool awaited = state_ == State::kAwaitingPlan && plan.plan_id > request_->after_plan_id;
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
  const bool path_out = path_is_out();
  request_.reset();
  // an empty tour: the path the tracker may still follow leads nowhere now
  if (sequence.viewpoints.empty() && path_out) send_maneuver(msg::Maneuver::Kind::kStop, {}, 0);
  backoff_.reset();
  enter(tour_->done() ? State::kIdle : State::kToPlan);
  consecutive_failures_ = 0;
  traffic_->reset();
  ++stats_.tours;
  if (!tour_pub_.valid()) return;
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
  if (state_ == State::kAwaitingPlan) return;
  request_ = Request{.after_plan_id = last_plan_id_,
                     .since_s = now_s(),
                     .path_out = path_is_out(),
                     .reason = reason,
                     .because_of_robot = because_of,
                     // a request made before the robot published any mode but kPlanning
                     // since its last one (the new tour's first goals fail at once, the
                     // redundancy check fires at once) waits for replan_timeout_s, as when
                     // a request was the mode turning to kPlanning: answered at once, two
                     // robots' dist-TSGA planners traded clusters back and forth (31
                     // redundancy requests in the indoor pair of bench explore --quick)
                     .unsent = published_mode_ != Mode::kPlanning};
  enter(State::kAwaitingPlan);
  pending_.reset();  // computed before the reason to replan
  ++stats_.replans;
  mode_ = Mode::kPlanning;
  SCANCREW_LOG_DEBUG("%s: asks for a new plan: %s%s%s", qualified_name().c_str(), to_string(reason),
                     detail.empty() ? "" : ": ", detail.c_str());
}

// Sent at the end of the tick, after the robot state: the high-level planner plans on the
// pose and mode of that state.
void LowLevelPlanner::send_request(bool repeated) {
  request_->unsent = false;
  if (auto loan = request_pub_.loan()) {
    msg::ReplanRequest& m = **loan;
    m.header.stamp_ns = clock().now_ns();
    m.reason = request_->reason;
    m.because_of_robot = request_->because_of_robot;
    m.after_plan_id = request_->after_plan_id;
    m.repeated = repeated;
    (void)request_pub_.publish(std::move(*loan));
  }
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
  if (state_ == State::kAwaitingPlan && now_s() - request_->since_s > config_.replan_timeout_s) {
    request_->since_s = now_s();  // unanswered: asked again
    mode_ = Mode::kPlanning;
    publish_state();
    send_request(true);
    return;
  }
  switch (state_) {
    case State::kAwaitingPlan:
      mode_ = Mode::kPlanning;
      break;
    case State::kIdle:
      mode_ = Mode::kIdle;  // the high-level planner reallocates to an idle robot
      make_way();
      break;
    case State::kToPlan:
      if (!follow_checks()) plan_to_goal();
      break;
    case State::kFollowing:
    case State::kBackingOff:
      watch_motion();
      watch_stall();
      break;
  }
  publish_state();
  if (state_ == State::kAwaitingPlan && request_->unsent) send_request(false);
}

void LowLevelPlanner::publish_state() {
  auto loan = state_pub_.loan();
  if (!loan) return;
  msg::RobotState& s = **loan;
  s.T_world_body = pose_->T_world_body;
  s.velocity_mps = pose_->linear_velocity_mps;
  s.mode = mode_;
  published_mode_ = mode_;
  s.plan_id = tour_ ? tour_->plan_id : 0;
  s.current_cluster = tour_ && !tour_->done() ? tour_->goal_cluster() : 0;
  s.path_index = tour_ ? static_cast<uint32_t>(tour_->next) : 0;
  s.steps_remaining = tour_ ? static_cast<uint32_t>(tour_->remaining()) : 0;
  s.path_length_m = stats_.path_length_m;
  s.backing_off = state_ == State::kBackingOff;
  s.held_by_robot = mode_ == Mode::kWaiting || mode_ == Mode::kSteppingAside ? held_by_ : 0;
  (void)state_pub_.publish(std::move(*loan));
}

const char* to_string(LowLevelPlanner::State s) {
  switch (s) {
    case LowLevelPlanner::State::kIdle:
      return "idle";
    case LowLevelPlanner::State::kToPlan:
      return "to_plan";
    case LowLevelPlanner::State::kFollowing:
      return "following";
    case LowLevelPlanner::State::kBackingOff:
      return "backing_off";
    case LowLevelPlanner::State::kAwaitingPlan:
      return "awaiting_plan";
  }
  return "?";
}

void LowLevelPlanner::enter(State next) {
  if (next == state_) return;
  SCANCREW_LOG_DEBUG("%s: %s -> %s", qualified_name().c_str(), to_string(state_), to_string(next));
  state_ = next;
}

bool LowLevelPlanner::path_is_out() const {
  switch (state_) {
    case State::kFollowing:
    case State::kBackingOff:
      return true;
    case State::kAwaitingPlan:
      return request_->path_out;
    default:
      return false;
  }
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
