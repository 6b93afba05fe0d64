#include "components/path_tracker/path_tracker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::path_tracker {

namespace {
constexpr double kDegToRad = M_PI / 180.0;

bool finite(const msg::Pose3& p) {
  return std::isfinite(p.position.x) && std::isfinite(p.position.y) &&
         std::isfinite(p.position.z) && std::isfinite(p.orientation.w) &&
         std::isfinite(p.orientation.x) && std::isfinite(p.orientation.y) &&
         std::isfinite(p.orientation.z) &&
         (p.orientation.w * p.orientation.w + p.orientation.x * p.orientation.x +
          p.orientation.y * p.orientation.y + p.orientation.z * p.orientation.z) > 1e-12;
}

bool finite(const msg::Waypoint& w) {
  return std::isfinite(w.position.x) && std::isfinite(w.position.y) &&
         std::isfinite(w.position.z) && std::isfinite(w.yaw_rad);
}

bool same_path(const std::vector<msg::Waypoint>& a, const std::vector<msg::Waypoint>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](const msg::Waypoint& x, const msg::Waypoint& y) {
                      return x.position.x == y.position.x && x.position.y == y.position.y &&
                             x.position.z == y.position.z && x.yaw_rad == y.yaw_rad;
                    });
}
}  // namespace

PathTracker::Config PathTracker::read_config(ParamReader& p) {
  Config c;
  p.optional("rate_hz", c.rate_hz, {1, 1000}).doc("command rate (Hz)");
  p.optional("look_ahead_m", c.look_ahead.distance_m, {0.05, 20})
      .doc("look-ahead distance along the path (m)");
  p.optional("search_window_m", c.look_ahead.search_window_m, {0.1, 100})
      .doc("how far past the progress the projection may move per tick (m)");
  p.choice("yaw_source", c.look_ahead.yaw_source, kYawSourceNames)
      .doc("the target's yaw: tangent (direction of travel) or waypoints (the path's own yaws)");
  p.optional("gain", c.law.gain, {0.01, 100}).doc("PBVS adaptive gain λ(∞)");
  p.optional("gain_at_zero", c.law.gain_at_zero, {0.01, 100})
      .doc("PBVS adaptive gain λ(0) (≥ gain)");
  p.optional("gain_slope", c.law.gain_slope, {0.01, 1000}).doc("PBVS adaptive gain slope λ'(0)");
  if (c.law.gain_at_zero < c.law.gain)
    p.report("gain_at_zero", "must be at least gain (equal: a constant gain)");
  p.optional("ground_max_speed_mps", c.ground.max_speed_mps, {0.01, 20})
      .doc("ground robots' speed limit (m/s; table 5.3)");
  p.optional("ground_max_yaw_rate_radps", c.ground.max_yaw_rate_radps, {0.01, 20})
      .doc("ground robots' yaw rate limit (rad/s)");
  p.optional("heading_gain", c.ground.heading_gain, {0.01, 100})
      .doc("ground robots far from the target: ω = heading_gain·α (1/s)");
  double turn_deg = c.ground.turn_in_place_rad / kDegToRad;
  p.optional("turn_in_place_deg", turn_deg, {1, 180})
      .doc("heading error above which a ground robot turns on the spot (degrees)");
  c.ground.turn_in_place_rad = turn_deg * kDegToRad;
  p.optional("align_radius_m", c.ground.align_radius_m, {0, 10})
      .doc("ground robots turn to the goal's yaw within this (m; ≤ position_tolerance_m)");
  p.optional("ground_reverse_max_m", c.ground.reverse_max_m, {0, 10})
      .doc(
          "a goal this close behind, with about the robot's yaw, is reached backwards (m; 0: "
          "never)");
  p.optional("ground_reverse_min_radius_m", c.ground.reverse_min_radius_m, {0, 10})
      .doc("backing turns on arcs at least this wide (m; 0: no limit)");
  p.optional("multirotor_max_speed_mps", c.multirotor.max_speed_mps, {0.01, 20})
      .doc("multirotors' horizontal speed limit (m/s; tables 3.1, 4.1)");
  p.optional("multirotor_max_vertical_speed_mps", c.multirotor.max_vertical_speed_mps, {0.01, 20})
      .doc("multirotors' vertical speed limit (m/s)");
  p.optional("multirotor_max_yaw_rate_radps", c.multirotor.max_yaw_rate_radps, {0.01, 20})
      .doc("multirotors' yaw rate limit (rad/s)");
  p.optional("position_tolerance_m", c.position_tolerance_m, {0.001, 10})
      .doc("goal and aside pose reached within this (m; horizontal for ground robots)");
  double yaw_tol_deg = c.yaw_tolerance_rad / kDegToRad;
  p.optional("yaw_tolerance_deg", yaw_tol_deg, {0.01, 180})
      .doc("goal and aside pose reached within this yaw (degrees)");
  c.yaw_tolerance_rad = yaw_tol_deg * kDegToRad;
  if (c.ground.align_radius_m > c.position_tolerance_m)
    p.report("align_radius_m", "must not exceed position_tolerance_m (the robot would stop short)");
  p.optional("pose_timeout_s", c.pose_timeout_s, {0.01, 100}).doc("older poses: stop (kLost) (s)");
  p.optional("lost_turn_rate_radps", c.lost_turn_rate_radps, {0, 5})
      .doc(
          "ground robot whose odometry lost track: turn on the spot at this rate until it resumes "
          "(rad/s; 0: hold still)");
  p.optional("lost_turn_after_s", c.lost_turn_after_s, {0, 3600})
      .doc("... once it has held still this long without the track coming back (s)");
  p.optional("initial_turn_deg", c.initial_turn_deg, {0, 1080})
      .doc(
          "ground robot: the first scan, a turn on the spot this far before it follows any path "
          "(degrees; 0: none)");
  p.optional("predict_pose", c.predict_pose)
      .doc("move the last pose by the commands sent since its stamp");
  p.optional("new_plan_resumes", c.new_plan_resumes).doc("a new plan clears a stop or step-aside");
  p.optional("publish_state", c.publish_state)
      .doc("false: no tracker_state (a mission reads none)");
  return c;
}

PathTracker::PathTracker(ComponentContext context, Config config)
    : Component(std::move(context)),
      config_(config),
      look_ahead_(config_.look_ahead),
      law_(config_.law) {}

Result<void, std::string> PathTracker::on_configure() {
  for (const TeamMember& m : team())
    if (m.id == robot_id()) ground_ = m.kind == robot::RobotKind::kGround;
  turning_first_ = ground_ && config_.initial_turn_deg > 0;
  LookAheadConfig la = config_.look_ahead;
  la.planar = ground_;
  look_ahead_ = LookAhead(la);
  cmd_ = create_publisher<msg::VelocityCommand>("cmd_vel");
  if (config_.publish_state) state_ = create_publisher<msg::RobotState>("tracker_state");
  create_subscription<msg::LocalPath>("local_path", {.depth = 2},
                                      [this](Sample<msg::LocalPath>&& s) { on_path(*s); });
  create_subscription<msg::Odometry>("pose", {.depth = 4},
                                     [this](Sample<msg::Odometry>&& s) { on_pose(*s); });
  create_subscription<msg::Maneuver>("maneuver", {.depth = 4},
                                     [this](Sample<msg::Maneuver>&& s) { on_maneuver(*s); });
  mark_input_optional("maneuver");  // the traffic policy's; a replay has none
  create_timer(std::chrono::nanoseconds(std::llround(1e9 / config_.rate_hz)),
               [this] { on_tick(); });
  return {};
}

void PathTracker::warn_once(bool& flag, const char* what) {
  if (flag) return;
  flag = true;
  SCANCREW_LOG_WARN("%s: %s (logged once)", qualified_name().c_str(), what);
}

void PathTracker::on_path(const msg::LocalPath& path) {
  if (have_plan_ && path.plan_id < plan_id_) {
    ++stale_plans_;
    warn_once(logged_stale_plan_, "a stale plan (older plan_id) was ignored");
    return;
  }
  if (have_plan_ && path.plan_id == plan_id_ && same_path(path.waypoints, path_)) return;
  const bool new_plan = !have_plan_ || path.plan_id != plan_id_;
  have_plan_ = true;
  if (new_plan) reversing_ = false;
  plan_id_ = path.plan_id;
  path_ = path.waypoints;
  done_ = false;
  next_index_ = 0;
  if (auto ok = look_ahead_.set_path(path_); !ok) {
    path_ok_ = false;
    if (!logged_bad_path_) {
      logged_bad_path_ = true;
      SCANCREW_LOG_WARN("%s: plan %llu refused (%s): holding still (logged once)",
                        qualified_name().c_str(), static_cast<unsigned long long>(plan_id_),
                        ok.error().c_str());
    }
  } else {
    path_ok_ = true;
  }
  if (new_plan && config_.new_plan_resumes) order_ = Order::kNone;
  on_tick();
}

void PathTracker::on_pose(const msg::Odometry& odom) {
  pose_seen_ = true;
  if (odom.tracking_quality <= 0 || !finite(odom.T_world_body)) {
    pose_valid_ = false;
    const bool lost = odom.tracking_quality <= 0 && finite(odom.T_world_body);
    if (lost && !tracking_lost_) lost_since_ns_ = clock().now_ns();
    tracking_lost_ = lost;
    warn_once(logged_lost_, ground_ && tracking_lost_ && config_.lost_turn_rate_radps > 0
                                ? "tracking lost: holding still, then turning on the spot after "
                                  "lost_turn_after_s until it resumes"
                                : "no usable pose (NaN or tracking lost): holding still");
    return;
  }
  tracking_lost_ = false;
  const Eigen::Vector3d position = msg::to_eigen(odom.T_world_body.position);
  if (have_pose_) travelled_m_ += (position - last_position_).norm();
  last_position_ = position;
  pose_ = odom;
  have_pose_ = pose_valid_ = true;
  pose_unused_ = true;
  if (turning_first_) {
    const double yaw = yaw_of(msg::to_eigen(odom.T_world_body).linear());
    if (turn_last_yaw_) turned_rad_ += std::abs(std::remainder(yaw - *turn_last_yaw_, 2 * M_PI));
    turn_last_yaw_ = yaw;
    if (turned_rad_ >= config_.initial_turn_deg * kDegToRad) {
      turning_first_ = false;
      SCANCREW_LOG_INFO("%s: first scan done (turned %.0f deg on the spot)",
                        qualified_name().c_str(), turned_rad_ / kDegToRad);
    }
  }
  while (sent_.size() > 1 && sent_[1].stamp_ns <= pose_.header.stamp_ns) sent_.pop_front();
}

void PathTracker::on_maneuver(const msg::Maneuver& maneuver) {
  reversing_ = false;  // a new goal (the aside pose) or back to the path
  switch (maneuver.kind) {
    case msg::Maneuver::Kind::kStop:
      order_ = Order::kStop;
      break;
    case msg::Maneuver::Kind::kStepAside:
      turning_first_ = false;  // out of a teammate's way comes first
      if (!finite(maneuver.aside)) {
        // cannot go there: stopping is the safe reading of the order
        warn_once(logged_bad_aside_, "step-aside to a non-finite pose: stopping instead");
        order_ = Order::kStop;
      } else {
        order_ = Order::kStepAside;
        aside_ = maneuver.aside;
      }
      break;
    case msg::Maneuver::Kind::kResume:
      order_ = Order::kNone;
      break;
  }
  on_tick();  // at once, not at the next tick
}

Eigen::Isometry3d PathTracker::predicted_pose(int64_t now_ns) const {
  Eigen::Isometry3d T_world_body = msg::to_eigen(pose_.T_world_body);
  if (!config_.predict_pose || sent_.empty()) return T_world_body;
  Eigen::Vector3d p = T_world_body.translation();
  double yaw = yaw_of(T_world_body.linear());
  // integrate the piecewise-constant commands from the pose's stamp to now (midpoint yaw)
  for (size_t i = 0; i < sent_.size(); ++i) {
    const int64_t t0 = std::max(sent_[i].stamp_ns, pose_.header.stamp_ns);
    const int64_t t1 = i + 1 < sent_.size() ? sent_[i + 1].stamp_ns : now_ns;
    if (t1 <= t0) continue;
    const double dt = 1e-9 * static_cast<double>(t1 - t0);
    const SentCommand& c = sent_[i];
    const double mid = yaw + 0.5 * c.yaw_rate * dt;
    p += Eigen::Vector3d(std::cos(mid) * c.vx - std::sin(mid) * c.vy,
                         std::sin(mid) * c.vx + std::cos(mid) * c.vy, c.vz) *
         dt;
    yaw += c.yaw_rate * dt;
  }
  // keep the estimate's roll and pitch; only yaw and position move
  const double yaw0 = yaw_of(T_world_body.linear());
  Eigen::Isometry3d out = T_world_body;
  out.linear() = Eigen::AngleAxisd(yaw - yaw0, Eigen::Vector3d::UnitZ()) * T_world_body.linear();
  out.translation() = p;
  return out;
}

std::pair<double, double> PathTracker::errors_to(const Eigen::Isometry3d& T_world_body,
                                                 const msg::Waypoint& w) const {
  Eigen::Vector3d d = msg::to_eigen(w.position) - T_world_body.translation();
  if (ground_) d.z() = 0;
  return {d.norm(), std::abs(std::remainder(w.yaw_rad - yaw_of(T_world_body.linear()), 2 * M_PI))};
}

bool PathTracker::reverse_to(const Eigen::Isometry3d& T_world_body, const msg::Waypoint& goal) {
  if (!ground_ || config_.ground.reverse_max_m <= 0) return reversing_ = false;
  const Eigen::Vector2d d = (msg::to_eigen(goal.position) - T_world_body.translation()).head<2>();
  const double yaw = yaw_of(T_world_body.linear());
  if (d.norm() > config_.ground.reverse_max_m ||
      d.dot(Eigen::Vector2d(std::cos(yaw), std::sin(yaw))) >= 0)
    return reversing_ = false;  // far, or ahead
  const double back_error =
      std::abs(std::remainder(std::atan2(d.y(), d.x()) - yaw - M_PI, 2 * M_PI));
  // once backing, until there, or until the goal is off the back by more than
  // turn_in_place_rad (an arc too wide to reach it passes it by: then forwards)
  if (reversing_) return reversing_ = back_error <= config_.ground.turn_in_place_rad;
  // start backing only when neither turning the back to the goal nor turning to its yaw
  // can end it: the two turns together within turn_in_place_rad. A looser test flipped a
  // robot between backing (its back turned to the goal, its yaw off the goal's) and
  // driving forwards (turning back round), on the spot for 300 s (4-robot team)
  const double yaw_error = std::abs(std::remainder(goal.yaw_rad - yaw, 2 * M_PI));
  return reversing_ = back_error + yaw_error <= config_.ground.turn_in_place_rad;
}

void PathTracker::steer(const Eigen::Isometry3d& T_world_body, const Eigen::Vector3d& target_m,
                        double target_yaw_rad, const msg::Waypoint& goal, bool may_reverse,
                        bool final_pose, msg::VelocityCommand& cmd) {
  Eigen::Vector3d target = target_m;
  if (ground_) target.z() = T_world_body.translation().z();
  const LawOutput law = law_.compute(T_world_body, level_pose(target, target_yaw_rad));
  if (ground_) {
    const UnicycleCommand u =
        to_unicycle(law, config_.ground, may_reverse && reverse_to(T_world_body, goal), final_pose);
    cmd.linear_mps = {u.v_mps, 0.0, 0.0};
    cmd.yaw_rate_radps = u.omega_radps;
  } else {
    const MultirotorCommand m = to_multirotor(law, config_.multirotor);
    cmd.linear_mps = msg::to_msg(m.linear_mps);
    cmd.yaw_rate_radps = m.yaw_rate_radps;
  }
}

void PathTracker::on_tick() {
  using Mode = msg::RobotState::Mode;
  const int64_t now = clock().now_ns();
  msg::VelocityCommand cmd;  // zero unless moving
  Mode mode = Mode::kIdle;
  const bool pose_fresh =
      have_pose_ && pose_valid_ &&
      1e-9 * static_cast<double>(now - pose_.header.stamp_ns) <= config_.pose_timeout_s;
  if (have_pose_ && pose_valid_ && !pose_fresh)
    warn_once(logged_stale_pose_, "the pose is older than pose_timeout_s: holding still");

  if (order_ == Order::kStop) {
    mode = Mode::kStopped;
  } else if (!pose_fresh) {
    mode = pose_seen_ ? Mode::kLost : Mode::kIdle;  // kIdle: no pose message yet
    // a ground robot whose odometry lost track and did not find it again at rest within
    // lost_turn_after_s turns on the spot: the same view (a blank wall, a plain box face)
    // would never give it back, and a turn in place is what the odometry bridges best (the
    // gyro turns its last pose; the position does not move). Turning at once lost the
    // track again and again in the parking lot (776 losses in a 900 s pair mission; at
    // rest first: 2)
    if (ground_ && tracking_lost_ && !pose_valid_ &&
        1e-9 * static_cast<double>(now - lost_since_ns_) >= config_.lost_turn_after_s)
      cmd.yaw_rate_radps = config_.lost_turn_rate_radps;
  } else {
    const Eigen::Isometry3d T_world_body = predicted_pose(now);
    if (turning_first_ && order_ == Order::kNone) {
      mode = Mode::kMoving;
      cmd.yaw_rate_radps = config_.ground.max_yaw_rate_radps;  // as fast as it turns
    } else if (order_ == Order::kStepAside) {
      const auto [dp, dyaw] = errors_to(T_world_body, aside_);
      if (dp <= config_.position_tolerance_m && dyaw <= config_.yaw_tolerance_rad) {
        mode = Mode::kWaiting;
      } else {
        mode = Mode::kSteppingAside;
        steer(T_world_body, msg::to_eigen(aside_.position), aside_.yaw_rad, aside_, true, true,
              cmd);
      }
    } else if (!have_plan_ || !path_ok_) {
      mode = Mode::kIdle;
    } else if (done_) {
      mode = Mode::kDone;
    } else {
      const LookAheadTarget target = look_ahead_.update(T_world_body.translation());
      next_index_ = target.next_index;
      const auto [dp, dyaw] = errors_to(T_world_body, look_ahead_.final_waypoint());
      if (target.at_end && dp <= config_.position_tolerance_m &&
          dyaw <= config_.yaw_tolerance_rad) {
        done_ = true;
        ++plans_done_;
        done_position_error_m_ = dp;
        done_yaw_error_rad_ = dyaw;
        done_stamp_ns_ = now;
        next_index_ = static_cast<uint32_t>(path_.size());
        mode = Mode::kDone;
        SCANCREW_LOG_INFO("%s: plan %llu done (%.3f m, %.1f deg from the goal, %.1f m travelled)",
                          qualified_name().c_str(), static_cast<unsigned long long>(plan_id_), dp,
                          dyaw / kDegToRad, travelled_m_);
      } else {
        mode = Mode::kMoving;
        // backwards only along the path's last segment: a path with a bend behind the robot
        // would turn it round, then forwards again (the 4-robot team stalled so for 300 s)
        const bool last_segment = target.next_index + 1 >= path_.size();
        steer(T_world_body, target.position_m, target.yaw_rad, look_ahead_.final_waypoint(),
              last_segment, target.at_end, cmd);
      }
    }
  }
  if (mode != Mode::kLost && mode != Mode::kIdle) logged_lost_ = logged_stale_pose_ = false;
  publish(cmd, now, mode);
  if (pose_fresh) record_age(now);
}

void PathTracker::record_age(int64_t now_ns) {
  const int64_t age = now_ns - pose_.header.stamp_ns;
  command_age_.record(age);
  if (!pose_unused_) return;
  pose_unused_ = false;
  ++poses_used_;
  first_use_age_.record(age);
}

void PathTracker::summarize(RunSummary& into) const {
  const auto ms = [](uint64_t ns) { return static_cast<double>(ns) * 1e-6; };
  RunSummary::CommandLatency& l = into.command_latency[robot_id()];
  l.commands = command_age_.count();
  l.poses = poses_used_;
  l.age_p50_ms = ms(command_age_.percentile_ns(0.5));
  l.age_p99_ms = ms(command_age_.percentile_ns(0.99));
  l.age_max_ms = ms(command_age_.max_ns());
  l.first_use_p50_ms = ms(first_use_age_.percentile_ns(0.5));
  l.first_use_p99_ms = ms(first_use_age_.percentile_ns(0.99));
  l.first_use_max_ms = ms(first_use_age_.max_ns());
}

void PathTracker::publish(const msg::VelocityCommand& cmd, int64_t now_ns,
                          msg::RobotState::Mode mode) {
  mode_ = mode;
  // remember what was sent, for the prediction (one entry per stamp)
  SentCommand sent{now_ns, cmd.linear_mps.x, cmd.linear_mps.y, cmd.linear_mps.z,
                   cmd.yaw_rate_radps};
  if (!sent_.empty() && sent_.back().stamp_ns == now_ns)
    sent_.back() = sent;
  else
    sent_.push_back(sent);
  if (sent_.size() > 1024) sent_.pop_front();  // bounded, whatever the pose rate

  if (auto loan = cmd_.loan()) {
    msg::VelocityCommand& out = **loan;
    out = cmd;
    out.header.stamp_ns = now_ns;
    (void)cmd_.publish(std::move(*loan));
  }
  if (!state_.valid()) return;
  if (auto loan = state_.loan()) {
    msg::RobotState& s = **loan;
    s = {};
    s.header.stamp_ns = now_ns;
    s.T_world_body = pose_.T_world_body;
    s.velocity_mps = pose_.linear_velocity_mps;  // world frame, from the pose estimate
    s.mode = mode;
    s.plan_id = plan_id_;
    s.path_index = next_index_;
    s.steps_remaining =
        static_cast<uint32_t>(path_.size()) - std::min<uint32_t>(next_index_, path_.size());
    s.path_length_m = travelled_m_;
    (void)state_.publish(std::move(*loan));
  }
}

SCANCREW_REGISTER_COMPONENT(PathTracker, "path_tracker")

}  // namespace scancrew::path_tracker
