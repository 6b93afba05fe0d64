#include "bench/pipeline/run_latency.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace scancrew::bench {

namespace {

using Json = nlohmann::ordered_json;

// "p50 / p99 / max" of a {"p50", "p99", "max"} object, in ms.
std::string triple(const Json& j) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.1f / %.1f / %.1f", j.value("p50", 0.0), j.value("p99", 0.0),
                j.value("max", 0.0));
  return buf;
}

void print_table(const std::string& run_dir, const Json& m, const Json& robots) {
  const bool wall = m.contains("wall_clock");
  std::printf("run %s: %s clock, %.1f s (%.1f s wall)\n", run_dir.c_str(), wall ? "wall" : "sim",
              m.value("sim_time_s", 0.0), m.value("wall_time_s", 0.0));
  if (wall) {
    const Json& w = m["wall_clock"];
    std::printf(
        "simulator: %.1f s of physics, %llu ticks, %llu late, %llu at the catch-up bound, lag "
        "max %.3f s\n",
        w.value("simulated_s", 0.0), w.value("ticks", 0ull), w.value("late_ticks", 0ull),
        w.value("capped_ticks", 0ull), w.value("max_lag_s", 0.0));
  }
  std::printf("%-10s %9s %7s  %-28s %-28s\n", "robot", "commands", "poses",
              "camera->command ms p50/p99/max", "pose age ms p50/p99/max");
  for (const Json& r : robots) {
    const Json& l = r["command_latency"];
    std::printf("%-10s %9llu %7llu  %-28s %-28s\n", r.value("namespace", "?").c_str(),
                l.value("commands", 0ull), l.value("poses", 0ull),
                triple(l["first_use_ms"]).c_str(), triple(l["age_ms"]).c_str());
  }
}

}  // namespace

int print_run_latency(const std::string& run_dir, bool json) {
  const std::filesystem::path path = std::filesystem::path(run_dir) / "metrics.json";
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "bench pipeline --run: cannot read %s (a run directory of scancrew run)\n",
                 path.c_str());
    return 1;
  }
  Json m;
  try {
    m = Json::parse(in);
  } catch (const Json::exception& e) {
    std::fprintf(stderr, "bench pipeline --run: %s: %s\n", path.c_str(), e.what());
    return 1;
  }
  Json robots = Json::array();
  for (const Json& r : m.value("robots", Json::array()))
    if (r.contains("command_latency")) robots.push_back(r);
  if (robots.empty()) {
    std::fprintf(stderr,
                 "bench pipeline --run: %s: no robot has command_latency (no path_tracker, or a "
                 "run made before it was measured)\n",
                 path.c_str());
    return 1;
  }
  if (!json) {
    print_table(run_dir, m, robots);
    return 0;
  }
  Json out{{"run", run_dir},
           {"clock", m.contains("wall_clock") ? "wall" : "sim"},
           {"sim_time_s", m.value("sim_time_s", 0.0)},
           {"wall_time_s", m.value("wall_time_s", 0.0)}};
  if (m.contains("wall_clock")) out["wall_clock"] = m["wall_clock"];
  Json list = Json::array();
  for (const Json& r : robots)
    list.push_back(
        Json{{"namespace", r.value("namespace", "")}, {"command_latency", r["command_latency"]}});
  out["robots"] = std::move(list);
  std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace scancrew::bench
