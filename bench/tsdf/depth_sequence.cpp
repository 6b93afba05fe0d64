#include "bench/tsdf/depth_sequence.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "interfaces/eigen_conversions.hpp"
#include "sim/team_sim.hpp"

namespace scancrew::bench {

namespace {

// The loop of `scancrew bench perception` (bench/perception/sequence.cpp): 1.8 m either
// side of the pillars, 3 m clear of the end walls; 37.2 m.
constexpr std::array<std::array<double, 2>, 4> kLoop = {
    {{7.5, -1.8}, {7.5, 1.8}, {-7.5, 1.8}, {-7.5, -1.8}}};

// components/waypoint_driver's defaults
constexpr double kSpeedMps = 0.5, kYawGain = 1.5, kMaxYawRate = 0.5, kArriveRadiusM = 0.5;
constexpr int64_t kCommandPeriodNs = 100'000'000;  // 10 Hz

// Square pixels: the vertical FOV that a 90° horizontal FOV gives at this aspect.
double fov_v_for(uint32_t w, uint32_t h) {
  return 2.0 * std::atan(static_cast<double>(h) / w) * 180.0 / M_PI;
}

// The waypoint_driver's law for a ground robot: turn towards the waypoint, drive forward
// as much as it faces it.
class LoopDriver {
 public:
  msg::VelocityCommand command(const msg::Pose3& T_world_body) {
    const double x = T_world_body.position.x, y = T_world_body.position.y;
    if (have_last_) driven_m_ += std::hypot(x - last_x_, y - last_y_);
    last_x_ = x;
    last_y_ = y;
    have_last_ = true;
    auto offset = [&] {
      return std::array<double, 2>{kLoop[target_][0] - x, kLoop[target_][1] - y};
    };
    if (std::hypot(offset()[0], offset()[1]) < kArriveRadiusM)
      target_ = (target_ + 1) % kLoop.size();
    const auto d = offset();
    const msg::Quat& q = T_world_body.orientation;
    const double yaw = std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
    const double heading_error = std::remainder(std::atan2(d[1], d[0]) - yaw, 2 * M_PI);
    msg::VelocityCommand c;
    c.yaw_rate_radps = std::clamp(kYawGain * heading_error, -kMaxYawRate, kMaxYawRate);
    c.linear_mps.x = kSpeedMps * std::max(0.0, std::cos(heading_error));
    return c;
  }
  double driven_m() const { return driven_m_; }

 private:
  size_t target_ = 0;
  bool have_last_ = false;
  double last_x_ = 0, last_y_ = 0, driven_m_ = 0;
};

}  // namespace

Result<std::unique_ptr<sim::TeamSim>, std::string> make_camera_sim(
    const sim::SceneSpec& scene, sim::RobotSpec robot, uint32_t width, uint32_t height,
    double min_range_m, double max_range_m, uint64_t seed) {
  robot.camera.width = width;
  robot.camera.height = height;
  robot.camera.fov_h_deg = 90.0;
  robot.camera.fov_v_deg = fov_v_for(width, height);
  robot.camera.min_range_m = min_range_m;
  robot.camera.max_range_m = max_range_m;
  if (const std::string problem = robot.camera.validate(); !problem.empty())
    return make_unexpected(problem);
  sim::TeamSimConfig config;
  config.seed = seed;
  config.mjcf.offscreen_width = std::max(config.mjcf.offscreen_width, width);
  config.mjcf.offscreen_height = std::max(config.mjcf.offscreen_height, height);
  return sim::TeamSim::create(scene, {robot}, config);
}

Result<DepthSequence, std::string> render_depth_sequence(const sim::SceneSpec& scene,
                                                         const DepthSequenceOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  sim::RobotSpec robot;
  robot.id = 1;
  robot.name = "robot1";
  robot.kind = robot::RobotKind::kGround;
  robot.start_x_m = kLoop[3][0];
  robot.start_y_m = kLoop[3][1];
  auto made =
      make_camera_sim(scene, robot, o.width, o.height, o.min_range_m, o.max_range_m, o.seed);
  if (!made) return make_unexpected(made.error());
  sim::TeamSim& s = **made;

  DepthSequence out;
  out.min_range_m = o.min_range_m;
  out.max_range_m = o.max_range_m;
  out.depth_m.reserve(static_cast<size_t>(o.frames));
  out.T_world_cam.reserve(static_cast<size_t>(o.frames));
  LoopDriver driver;
  msg::DepthImage depth;
  const auto frame_period_ns = static_cast<int64_t>(std::llround(o.frame_period_s * 1e9));
  int64_t next_frame_ns = 0;
  for (int64_t t = 0; static_cast<int>(out.depth_m.size()) < o.frames; t += kCommandPeriodNs) {
    // frames at multiples of the frame period, commands at 10 Hz in between
    s.step_until(t);
    if (s.time_ns() >= next_frame_ns) {
      if (auto r = s.render_stereo(0, nullptr, &depth); !r) return make_unexpected(r.error());
      s.make_noisy_depth(0, depth);
      out.intrinsics = depth.intrinsics;
      out.depth_m.push_back(depth.depth_m);
      out.T_world_cam.push_back(depth.T_world_cam);
      next_frame_ns += frame_period_ns;
      std::fprintf(stderr, "\rrendering %ux%u: frame %zu / %d", o.width, o.height,
                   out.depth_m.size(), o.frames);
    }
    s.set_velocity(0, driver.command(s.body_pose(0)));
  }
  std::fprintf(stderr, "\n");
  out.driven_m = driver.driven_m();
  out.sim_s = static_cast<double>(s.time_ns()) * 1e-9;
  out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

tsdf::DepthFrame depth_frame(const std::vector<float>& depth_m, const msg::CameraIntrinsics& k,
                             const msg::Pose3& T_world_cam) {
  tsdf::DepthFrame frame;
  frame.depth_m = depth_m.data();
  frame.size = depth_m.size();
  frame.width = k.width;
  frame.height = k.height;
  frame.fx = k.fx;
  frame.fy = k.fy;
  frame.cx = k.cx;
  frame.cy = k.cy;
  frame.T_world_cam = msg::to_eigen(T_world_cam);
  return frame;
}

}  // namespace scancrew::bench
