#include "bench/common/parking_lot_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace scancrew::bench {

std::string parking_lot_loop_launch(double duration_s, const std::string& robot_ns,
                                    const std::string& scene_path, uint64_t seed, uint32_t width,
                                    uint32_t height) {
  // square pixels at 90 degrees horizontally
  const double fov_v_deg = 2.0 * std::atan(static_cast<double>(height) / width) * 180.0 / M_PI;
  constexpr const char* kFormat = R"(
clock: sim
executor: {type: step}
run: {duration_s: %.1f, sim_step_s: 0.05, progress_period_s: 1.0}
robots:
  - {id: 1, namespace: %s, kind: ground, start: [-7.5, -1.8, 0, 0]}
remap: {pose: pose_gt}
components:
  - type: team_simulator
    per_robot: false
    params:
      scene: %s
      seed: %llu
      publish_depth: false
      ground_camera_width: %u
      ground_camera_height: %u
      ground_camera_fov_v_deg: %.6f
)";
  const auto llu_seed = static_cast<unsigned long long>(seed);
  const int length = std::snprintf(nullptr, 0, kFormat, duration_s, robot_ns.c_str(),
                                   scene_path.c_str(), llu_seed, width, height, fov_v_deg);
  std::string text(static_cast<size_t>(std::max(length, 0)), '\0');
  std::snprintf(text.data(), text.size() + 1, kFormat, duration_s, robot_ns.c_str(),
                scene_path.c_str(), llu_seed, width, height, fov_v_deg);
  return text;
}

}  // namespace scancrew::bench
