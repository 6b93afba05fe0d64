#include "bench/sim/sim_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>

#include "sim/team_sim.hpp"

namespace scancrew::bench {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Square pixels: the vertical FOV that a 90° horizontal FOV gives at this aspect.
double fov_v_for(uint32_t w, uint32_t h) {
  return 2.0 * std::atan(std::tan(M_PI / 4) * h / w) * 180.0 / M_PI;
}

sim::RobotSpec robot(uint32_t id, double x, double y, uint32_t w, uint32_t h) {
  sim::RobotSpec r;
  r.id = id;
  r.name = "robot" + std::to_string(id);
  r.start_x_m = x;
  r.start_y_m = y;
  r.camera.width = w;
  r.camera.height = h;
  r.camera.fov_v_deg = fov_v_for(w, h);
  r.camera.rate_hz = 5;
  return r;
}

// Free start positions in the parking lot (the default scene): a row along y = -6 m.
std::vector<sim::RobotSpec> team(int n, uint32_t w, uint32_t h) {
  std::vector<sim::RobotSpec> robots;
  robots.reserve(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    robots.push_back(robot(static_cast<uint32_t>(i + 1), -9.0 + 2.0 * i, -6.0, w, h));
  return robots;
}

std::unique_ptr<sim::TeamSim> make_sim(const sim::SceneSpec& scene,
                                       std::vector<sim::RobotSpec> robots) {
  auto made = sim::TeamSim::create(scene, std::move(robots), {});
  if (!made) {
    std::fprintf(stderr, "bench sim: %s\n", made.error().c_str());
    return nullptr;
  }
  return std::move(made).value();
}

// Times one stereo pair per render size and appends a row per size to out["render"]; false if
// the simulator could not be made.
bool time_stereo_renders(const sim::SceneSpec& scene, const SimBenchOptions& o,
                         nlohmann::json& out) {
  // 1. one stereo pair (left + right images, depth read back, noise model applied)
  for (auto [w, h] : {std::pair<uint32_t, uint32_t>{320, 256}, {640, 480}}) {
    auto made = make_sim(scene, team(1, w, h));
    if (!made) return false;
    auto& s = *made;
    msg::StereoFrame stereo;
    msg::DepthImage depth;
    std::vector<double> ms;
    for (int i = 0; i < o.renders + 5; ++i) {
      s.set_velocity(0, [] {
        msg::VelocityCommand c;
        c.yaw_rate_radps = 0.3;
        return c;
      }());
      s.step_until(s.time_ns() + 50'000'000);
      const auto t0 = Clock::now();
      (void)s.render_stereo(0, &stereo, &depth);
      s.make_noisy_depth(0, depth);
      if (i >= 5) ms.push_back(seconds_since(t0) * 1e3);
    }
    std::sort(ms.begin(), ms.end());
    out["render"].push_back({{"width", w},
                             {"height", h},
                             {"p50_ms", ms[ms.size() / 2]},
                             {"p90_ms", ms[ms.size() * 9 / 10]},
                             {"max_ms", ms.back()}});
  }
  return true;
}

// Times the team simulator for 1, 3 and 5 robots and appends a row per team to
// out["real_time_factor"]; false if the simulator could not be made.
bool time_team_sim(const sim::SceneSpec& scene, const SimBenchOptions& o, nlohmann::json& out) {
  // 2. the team simulator as the sim backend runs it: 10 ms physics ticks, 5 Hz cameras
  for (int n : {1, 3, 5}) {
    auto made = make_sim(scene, team(n, 320, 256));
    if (!made) return false;
    auto& s = *made;
    msg::StereoFrame stereo;
    msg::DepthImage depth;
    const int64_t tick = 10'000'000, frame = 200'000'000;
    const auto t0 = Clock::now();
    for (int64_t t = tick; t <= static_cast<int64_t>(o.sim_seconds * 1e9); t += tick) {
      for (int r = 0; r < n; ++r) {
        msg::VelocityCommand c;
        c.linear_mps.x = 0.3;
        c.yaw_rate_radps = 0.2 * (r % 2 ? 1 : -1);
        s.set_velocity(static_cast<size_t>(r), c);
      }
      s.step_until(t);
      for (int r = 0; r < n; ++r) {
        (void)s.imu(static_cast<size_t>(r));
        if (t % frame == 0) {
          (void)s.render_stereo(static_cast<size_t>(r), &stereo, &depth);
          s.make_noisy_depth(static_cast<size_t>(r), depth);
        }
      }
    }
    const double wall = seconds_since(t0);
    out["real_time_factor"].push_back({{"robots", n},
                                       {"camera", "320x256 at 5 Hz"},
                                       {"sim_s", o.sim_seconds},
                                       {"wall_s", wall},
                                       {"rtf", o.sim_seconds / wall}});
  }
  return true;
}

// Prints the render and real-time-factor tables from out as text.
void print_sim_tables(const std::string& scene_name, const SimBenchOptions& o,
                      const nlohmann::json& out) {
  std::printf("scene %s\n\nstereo pair (left + right + depth + noise model):\n",
              scene_name.c_str());
  std::printf("  %-10s %8s %8s %8s\n", "size", "p50_ms", "p90_ms", "max_ms");
  for (const auto& r : out["render"])
    std::printf("  %4dx%-5d %8.2f %8.2f %8.2f\n", r["width"].get<int>(), r["height"].get<int>(),
                r["p50_ms"].get<double>(), r["p90_ms"].get<double>(), r["max_ms"].get<double>());
  std::printf("\nteam simulator, cameras 320x256 at 5 Hz, 10 ms physics ticks, %.0f s simulated:\n",
              o.sim_seconds);
  std::printf("  %-7s %8s %8s\n", "robots", "wall_s", "rtf");
  for (const auto& r : out["real_time_factor"])
    std::printf("  %-7d %8.2f %8.2f\n", r["robots"].get<int>(), r["wall_s"].get<double>(),
                r["rtf"].get<double>());
}

}  // namespace

int run_sim_bench(const SimBenchOptions& o) {
  auto scene = sim::load_scene(o.scene_path);
  if (!scene) {
    for (const auto& e : scene.error()) std::fprintf(stderr, "%s\n", e.c_str());
    return 2;
  }
  nlohmann::json out;
  out["scene"] = scene->name;
  out["render"] = nlohmann::json::array();
  out["real_time_factor"] = nlohmann::json::array();

  if (!time_stereo_renders(*scene, o, out)) return 2;
  if (!time_team_sim(*scene, o, out)) return 2;

  if (o.json) {
    std::printf("%s\n", out.dump().c_str());
    return 0;
  }
  print_sim_tables(scene->name, o, out);
  return 0;
}

}  // namespace scancrew::bench
