#include "components/waypoint_driver/waypoint_driver.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::waypoint_driver {

WaypointDriver::Config WaypointDriver::read_config(ParamReader& p) {
  Config c;
  p.optional_list("waypoints_m", c.waypoints_m, 0, {-1e6, 1e6})
      .doc("x, y, z triples (world frame, m); z unused for ground robots");
  if (c.waypoints_m.empty() || c.waypoints_m.size() % 3 != 0)
    p.report("waypoints_m", "needs x, y, z triples, at least one");
  p.optional("loop", c.loop).doc("drive the waypoints again and again");
  p.optional("speed_mps", c.speed_mps, {0.01, 20}).doc("driving speed (m/s)");
  p.optional("yaw_gain", c.yaw_gain, {0.01, 100}).doc("yaw rate per heading error (1/s)");
  p.optional("max_yaw_rate_radps", c.max_yaw_rate_radps, {0.01, 10}).doc("yaw rate limit (rad/s)");
  p.optional("arrive_radius_m", c.arrive_radius_m, {0.01, 100})
      .doc("a waypoint this near is reached (m)");
  p.optional("rate_hz", c.rate_hz, {0.1, 1000}).doc("command rate (Hz)");
  p.optional("stop_after_m", c.stop_after_m, {0, 1e7})
      .doc("stop after driving this far (m; 0: never)");
  return c;
}

WaypointDriver::WaypointDriver(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> WaypointDriver::on_configure() {
  for (const TeamMember& m : team())
    if (m.id == robot_id()) ground_ = m.kind == robot::RobotKind::kGround;
  cmd_ = create_publisher<msg::VelocityCommand>("cmd_vel");
  create_subscription<msg::Odometry>("pose", {.depth = 4}, [this](Sample<msg::Odometry>&& s) {
    if (s->tracking_quality <= 0) return;
    pose_ = *s;
    have_pose_ = true;
  });
  create_timer(std::chrono::nanoseconds(std::llround(1e9 / config_.rate_hz)),
               [this] { on_tick(); });
  return {};
}

void WaypointDriver::on_tick() {
  if (!have_pose_) return;
  const Eigen::Isometry3d T_world_body = msg::to_eigen(pose_.T_world_body);
  const Eigen::Vector3d position = T_world_body.translation();
  if (have_last_) travelled_m_ += (position - msg::to_eigen(last_position_)).norm();
  last_position_ = pose_.T_world_body.position;
  have_last_ = true;

  const size_t count = config_.waypoints_m.size() / 3;
  auto waypoint = [&](size_t i) {
    return Eigen::Vector3d(config_.waypoints_m[3 * i], config_.waypoints_m[3 * i + 1],
                           config_.waypoints_m[3 * i + 2]);
  };
  auto offset = [&] {
    Eigen::Vector3d d = waypoint(target_) - position;
    if (ground_) d.z() = 0;
    return d;
  };
  if (!stopped_ && offset().norm() < config_.arrive_radius_m) {
    ++reached_;
    if (target_ + 1 < count || config_.loop) {
      target_ = (target_ + 1) % count;
    } else {
      stopped_ = true;
      SCANCREW_LOG_INFO("%s: last waypoint reached after %.1f m", qualified_name().c_str(),
                        travelled_m_);
    }
  }
  if (!stopped_ && config_.stop_after_m > 0 && travelled_m_ >= config_.stop_after_m) {
    stopped_ = true;
    SCANCREW_LOG_INFO("%s: stopped after %.1f m", qualified_name().c_str(), travelled_m_);
  }

  auto loan = cmd_.loan();
  if (!loan) return;
  msg::VelocityCommand& cmd = **loan;
  cmd.header.stamp_ns = pose_.header.stamp_ns;
  cmd.linear_mps = {};
  cmd.yaw_rate_radps = 0;
  if (!stopped_) {
    const Eigen::Vector3d d = offset();
    const Eigen::Vector3d forward = T_world_body.linear().col(0);
    const double heading_error =
        std::remainder(std::atan2(d.y(), d.x()) - std::atan2(forward.y(), forward.x()), 2 * M_PI);
    cmd.yaw_rate_radps = std::clamp(config_.yaw_gain * heading_error, -config_.max_yaw_rate_radps,
                                    config_.max_yaw_rate_radps);
    if (ground_) {
      cmd.linear_mps.x = config_.speed_mps * std::max(0.0, std::cos(heading_error));
    } else if (d.norm() > 1e-9) {
      cmd.linear_mps = msg::to_msg(
          Eigen::Vector3d(T_world_body.linear().transpose() * d.normalized() * config_.speed_mps));
    }
  }
  (void)cmd_.publish(std::move(*loan));
}

SCANCREW_REGISTER_COMPONENT(WaypointDriver, "waypoint_driver")

}  // namespace scancrew::waypoint_driver
