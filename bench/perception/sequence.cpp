#include "bench/perception/sequence.hpp"

#include <cstdio>

#include "bench/common/parking_lot_loop.hpp"
#include "components/recorder/recorder.hpp"
#include "components/waypoint_driver/waypoint_driver.hpp"
#include "executors/launch.hpp"

namespace scancrew::bench {

namespace {

std::string launch_text(const SequenceOptions& o) {
  const double speed = 0.5;  // m/s, thesis 5.3
  // an upper bound on the time: the driver slows in the turns
  const double duration = 1.5 * o.distance_m / speed + 10.0;
  char rest[2048];
  std::snprintf(rest, sizeof rest, R"(      publish_depth_gt: true
      ground_camera_rate_hz: 10
      imu_rate_hz: 100
  - type: waypoint_driver
    params: {waypoints_m: %s, speed_mps: %.2f, stop_after_m: %.3f}
  - type: recorder
    params: {path: %s, topics: [stereo, imu, pose_gt, depth_gt], queue_depth: 256}
)",
                kParkingLotLoop, speed, o.distance_m, o.out_path.c_str());
  return parking_lot_loop_launch(duration, "r1", o.scene_path, o.seed, o.width, o.height) + rest;
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
  info.sim_s = launch.run([&](double elapsed_s, double /*duration_s*/, bool /*final*/) {
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
