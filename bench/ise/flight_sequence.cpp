#include "bench/ise/flight_sequence.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench/tsdf/depth_sequence.hpp"
#include "interfaces/eigen_conversions.hpp"
#include "sim/team_sim.hpp"

namespace scancrew::bench {

namespace {

// components/waypoint_driver's arrival radius and command rate; a faster yaw than its
// default, so the camera follows the footprint round the corners
constexpr double kArriveRadiusM = 0.5, kYawGain = 1.5, kMaxYawRate = 1.0;
constexpr int64_t kCommandPeriodNs = 100'000'000;  // 10 Hz

double yaw_of(const Eigen::Isometry3d& T_world_body) {
  const Eigen::Vector3d forward = T_world_body.linear().col(0);
  return std::atan2(forward.y(), forward.x());
}

// The heading towards the footprint's nearest point; `fallback` inside the footprint.
double heading_to(const std::array<double, 4>& footprint, const Eigen::Vector3d& p,
                  double fallback) {
  const double x = std::clamp(p.x(), footprint[0], footprint[2]);
  const double y = std::clamp(p.y(), footprint[1], footprint[3]);
  if (x == p.x() && y == p.y()) return fallback;
  return std::atan2(y - p.y(), x - p.x());
}

// The lap's rectangle, standoff_m outside the footprint, and its altitude profile.
struct Lap {
  double x0, y0, x1, y1;
  double altitude_m, altitude_swing_m, swing_period_m;

  double perimeter_m() const { return 2 * ((x1 - x0) + (y1 - y0)); }

  // the lap at arc length s: counter-clockwise from the (max x, min y) corner, the
  // footprint on the left; the altitude swings about its mean
  Eigen::Vector3d at(double s) const {
    s = std::fmod(s, perimeter_m());
    const double z = altitude_m + altitude_swing_m * std::sin(2 * M_PI * s / swing_period_m);
    const double side_x_m = x1 - x0, side_y_m = y1 - y0;      // the sides' lengths
    if (s < side_y_m) return Eigen::Vector3d(x1, y0 + s, z);  // east side, northwards
    s -= side_y_m;
    if (s < side_x_m) return Eigen::Vector3d(x1 - s, y1, z);  // north side, westwards
    s -= side_x_m;
    if (s < side_y_m) return Eigen::Vector3d(x0, y1 - s, z);  // west side, southwards
    return Eigen::Vector3d(x0 + s - side_y_m, y0, z);         // south side, eastwards
  }
};

// Builds the lap from the options' footprint, standoff and altitude profile.
Lap lap_around(const FlightSequenceOptions& o) {
  const std::array<double, 4>& f = o.footprint_m;
  return Lap{f[0] - o.standoff_m, f[1] - o.standoff_m, f[2] + o.standoff_m, f[3] + o.standoff_m,
             o.altitude_m,        o.altitude_swing_m,  o.swing_period_m};
}

// The multirotor at the scene bounds' (max x, min y) corner, facing the footprint.
sim::RobotSpec lap_robot(const sim::SceneSpec& scene, const std::array<double, 4>& f,
                         double start_z_m, double speed_mps) {
  sim::RobotSpec robot;
  robot.id = 1;
  robot.name = "robot1";
  robot.kind = robot::RobotKind::kMultirotor;
  robot.start_x_m = scene.max_m.x;
  robot.start_y_m = scene.min_m.y;
  robot.start_z_m = start_z_m;
  robot.start_yaw_rad = heading_to(f, {robot.start_x_m, robot.start_y_m, robot.start_z_m}, 0.0);
  // commands are clamped to twice the nominal speed: room for the climbs
  robot.nominal_speed_mps = speed_mps;
  robot.camera.baseline_m = 0.11;
  robot.camera.mount_up_m = 0.0;
  return robot;
}

// Renders one noisy depth frame at along_m, records it in out, hands it to the sink and
// reports progress.
Result<void, std::string> take_frame(sim::TeamSim& s, msg::DepthImage& depth, double along_m,
                                     const FlightSequenceOptions& o, const FrameSink& sink,
                                     FlightSummary& out) {
  const auto r0 = std::chrono::steady_clock::now();
  if (auto r = s.render_stereo(0, nullptr, &depth); !r) return make_unexpected(r.error());
  s.make_noisy_depth(0, depth);
  out.render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
  out.intrinsics = depth.intrinsics;
  ++out.frames;
  out.flown_m = along_m;
  if (auto r = sink(depth); !r) return make_unexpected(r.error());
  if (out.frames % 10 == 0 || out.frames == o.frames)
    std::fprintf(stderr, "\rflight %ux%u: frame %d / %d", o.width, o.height, out.frames, o.frames);
  return {};
}

// The body-frame command for world velocity v_world, the yaw turning towards the footprint.
msg::VelocityCommand command_for(const Eigen::Isometry3d& T_world_body,
                                 const Eigen::Vector3d& v_world, const std::array<double, 4>& f) {
  msg::VelocityCommand c;
  c.linear_mps = msg::to_msg(Eigen::Vector3d(T_world_body.linear().transpose() * v_world));
  const double yaw = yaw_of(T_world_body);
  const double error =
      std::remainder(heading_to(f, T_world_body.translation(), yaw) - yaw, 2 * M_PI);
  c.yaw_rate_radps = std::clamp(kYawGain * error, -kMaxYawRate, kMaxYawRate);
  return c;
}

}  // namespace

Result<FlightSummary, std::string> fly_lap(const sim::SceneSpec& scene,
                                           const FlightSequenceOptions& o, const FrameSink& sink) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::array<double, 4>& f = o.footprint_m;
  const Lap lap = lap_around(o);
  if (!(lap.x1 > lap.x0 && lap.y1 > lap.y0 && o.speed_mps > 0 && o.frames > 0 &&
        o.swing_period_m > 0 && o.lap_fraction > 0 && o.lap_fraction <= 1))
    return make_unexpected(
        std::string("flight: empty lap, no speed, no frame, no period or a lap fraction "
                    "outside (0, 1]"));
  const double perimeter_m = lap.perimeter_m();

  const sim::RobotSpec robot = lap_robot(scene, f, lap.at(0).z(), o.speed_mps);
  auto made =
      make_camera_sim(scene, robot, o.width, o.height, o.min_range_m, o.max_range_m, o.seed);
  if (!made) return make_unexpected(made.error());
  sim::TeamSim& s = **made;

  FlightSummary out;
  msg::DepthImage depth;
  const double flight_m = perimeter_m * o.lap_fraction;
  const double spacing_m = flight_m / o.frames;
  const double dt_s = static_cast<double>(kCommandPeriodNs) * 1e-9;
  // the approach and the lap at the nominal speed, and as much again: a flight that does
  // not finish is a bug
  const double approach_m =
      (lap.at(0) - Eigen::Vector3d(robot.start_x_m, robot.start_y_m, robot.start_z_m)).norm();
  const auto limit_ns =
      static_cast<int64_t>(2e9 * (approach_m + flight_m) / o.speed_mps) + 10 * kCommandPeriodNs;
  bool lapping = false;  // false: approaching the lap's start
  double along_m = 0;    // arc length of the reference point on the lap
  double next_frame_m = 0;
  for (int64_t t = 0; out.frames < o.frames; t += kCommandPeriodNs) {
    if (t > limit_ns)
      return make_unexpected("flight: lap not finished after " + std::to_string(t / 1'000'000'000) +
                             " s of sim time");
    s.step_until(t);
    const Eigen::Isometry3d T_world_body = msg::to_eigen(s.body_pose(0));
    const Eigen::Vector3d p = T_world_body.translation();
    if (!lapping && (lap.at(0) - p).norm() < kArriveRadiusM) lapping = true;
    // frames at multiples of the spacing along the lap, commands at 10 Hz in between
    if (lapping && along_m >= next_frame_m) {
      if (auto r = take_frame(s, depth, along_m, o, sink, out); !r)
        return make_unexpected(r.error());
      next_frame_m += spacing_m;
    }
    // approach: straight at the lap's start (the waypoint_driver's multirotor law); lap:
    // onto the reference point a command period ahead (body-frame velocity)
    Eigen::Vector3d v_world;
    if (lapping) {
      along_m += o.speed_mps * dt_s;
      v_world = (lap.at(along_m) - p) / dt_s;
    } else {
      const Eigen::Vector3d d = lap.at(0) - p;
      v_world =
          d.norm() > 1e-9 ? Eigen::Vector3d(d.normalized() * o.speed_mps) : Eigen::Vector3d::Zero();
    }
    s.set_velocity(0, command_for(T_world_body, v_world, f));
  }
  std::fprintf(stderr, "\n");
  out.sim_s = static_cast<double>(s.time_ns()) * 1e-9;
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace scancrew::bench
