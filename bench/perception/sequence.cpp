#include "bench/perception/sequence.hpp"

#include <cmath>
#include <cstdio>

#include "components/recorder/recorder.hpp"
#include "components/waypoint_driver/waypoint_driver.hpp"
#include "executors/launch.hpp"

namespace scancrew::bench {

namespace {

// A loop around the three pillars (37.2 m): 1.8 m either side of them, 3 m clear of the
// end walls, every obstacle of the scene at least 0.9 m from the path.
constexpr const char* kLoop = "[7.5, -1.8, 0, 7.5, 1.8, 0, -7.5, 1.8, 0, -7.5, -1.8, 0]";

std::string launch_text(const SequenceOptions& o) {
  // square pixels at 90 degrees horizontally
  const double fov_v_deg = 2.0 * std::atan(static_cast<double>(o.height) / o.width) * 180.0 / M_PI;
  const double speed = 0.5;  // m/s, thesis 5.3
  // an upper bound on the time: the driver slows in the turns
  const double duration = 1.5 * o.distance_m / speed + 10.0;
  char text[2048];
  std::snprintf(text, sizeof text, R"(
clock: sim
executor: {type: step}
run: {duration_s: %.1f, sim_step_s: 0.05, progress_period_s: 1.0}
robots:
  - {id: 1, namespace: r1, kind: ground, start: [-7.5, -1.8, 0, 0]}
remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params:
      scene: %s
      seed: %llu
      publish_depth: false
      publish_depth_gt: true
      ground_camera_width: %u
      ground_camera_height: %u
      ground_camera_fov_v_deg: %.6f
      ground_camera_rate_hz: 10
      imu_rate_hz: 100
  - name: driver
    type: waypoint_driver
    params: {waypoints_m: %s, speed_mps: %.2f, stop_after_m: %.3f}
  - name: recorder
    type: recorder
    params: {path: %s, topics: [stereo, imu, pose_gt, depth_gt], queue_depth: 256}
)",
                duration, o.scene_path.c_str(), static_cast<unsigned long long>(o.seed), o.width,
                o.height, fov_v_deg, kLoop, speed, o.distance_m, o.out_path.c_str());
  return text;
}

}  // namespace

Result<SequenceInfo, std::string> record_sequence(const SequenceOptions& o) {
  auto made = Launch::from_string(launch_text(o), "bench_perception_record.yaml");
  if (!made) {
    std::string all;
    for (const std::string& e : made.error()) all += (all.empty() ? "" : "; ") + e;
    return make_unexpected(all);
  }
  Launch& launch = **made;
  auto* driver = launch.find_component<waypoint_driver::WaypointDriver>();
  auto* recorder = launch.find_component<recorder::Recorder>();
  if (driver == nullptr || recorder == nullptr)
    return make_unexpected(std::string("the recording launch lacks its driver or recorder"));
  SequenceInfo info;
  info.sim_s = launch.run([&](double elapsed_s, double /*duration_s*/) {
    std::fprintf(stderr, "\rrecording: %5.1f s sim, %5.1f / %.0f m driven", elapsed_s,
                 driver->travelled_m(), o.distance_m);
    if (driver->stopped()) launch.request_stop();
  });
  std::fprintf(stderr, "\n");
  info.driven_m = driver->travelled_m();
  info.messages = recorder->messages_written();
  if (recorder->write_errors() > 0)
    return make_unexpected("the recorder could not write " +
                           std::to_string(recorder->write_errors()) + " messages to " + o.out_path);
  if (info.driven_m < o.distance_m)
    return make_unexpected("the robot drove " + std::to_string(info.driven_m) + " m of " +
                           std::to_string(o.distance_m) + " m in " + std::to_string(info.sim_s) +
                           " s of sim time");
  return info;
}

}  // namespace scancrew::bench
