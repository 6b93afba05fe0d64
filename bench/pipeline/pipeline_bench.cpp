#include "bench/pipeline/pipeline_bench.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <thread>
#include <utility>

#include "bench/bench_stats.hpp"
#include "bench/pipeline/pipeline_trial.hpp"

namespace scancrew::bench {

namespace {

using Json = nlohmann::ordered_json;

constexpr double kMaxRateHz = 1000.0;  // the doubling stops here
// pairs of a first, unreported trial per size: the process's first matches and integrations
// pay one-off costs (OpenCV's buffers, page faults) that a running robot has paid long ago
constexpr size_t kWarmupPairs = 5;

Json to_json(const Figures& f) {
  return Json{{"n", f.n}, {"p50", f.p50}, {"p99", f.p99}, {"max", f.max}};
}

Json to_json(const Trial& t) {
  Json stages = Json::array();
  for (const Stage& s : t.stages)
    stages.push_back({{"stage", s.name},
                      {"input", s.input},
                      {"per", s.per},
                      {"callback_ms", to_json(s.callback_ms)},
                      {"latency_from_input_ms", to_json(s.from_input_ms)},
                      {"latency_from_capture_ms", to_json(s.from_capture_ms)}});
  return Json{{"rate_hz", t.rate_hz},
              {"fed_rate_hz", t.fed_rate_hz},
              {"pairs", t.pairs},
              {"integrated", t.integrated},
              {"dropped", t.dropped},
              {"camera_drops", t.camera_drops},
              {"stereo_queue_drops", t.stereo_queue_drops},
              {"depth_queue_drops", t.depth_queue_drops},
              {"drained", t.drained},
              {"sustained", t.sustained()},
              {"snapshots", t.snapshots},
              {"ise_runs", t.ise_runs},
              {"plans", t.plans},
              {"wall_s", t.wall_s},
              {"stages", stages},
              {"end_to_end_ms", to_json(t.end_to_end_ms)}};
}

void print_trial_line(const Trial& t) {
  std::fprintf(stderr,
               "  %7.2f Hz: %3llu pairs, %3llu dropped, %3llu ISE runs, %3llu plans, end to end "
               "p50 %7.1f ms p99 %7.1f ms%s\n",
               t.rate_hz, static_cast<unsigned long long>(t.pairs),
               static_cast<unsigned long long>(t.dropped),
               static_cast<unsigned long long>(t.ise_runs),
               static_cast<unsigned long long>(t.plans), t.end_to_end_ms.p50, t.end_to_end_ms.p99,
               t.drained ? "" : " (not drained)");
}

void print_stages(const char* title, const Trial& t) {
  std::printf("  %s: %.2f Hz, %llu pairs, %llu dropped\n", title, t.rate_hz,
              static_cast<unsigned long long>(t.pairs), static_cast<unsigned long long>(t.dropped));
  std::printf("    %-20s %-9s %5s | %-17s | %-17s | %-17s\n", "stage", "per", "n",
              "callback p50/p99", "from input p50/p99", "from pair p50/p99");
  for (const Stage& s : t.stages)
    std::printf("    %-20s %-9s %5zu | %7.1f %7.1f ms | %7.1f %7.1f ms | %7.1f %7.1f ms\n",
                s.name.c_str(), s.per.c_str(), s.from_input_ms.n, s.callback_ms.p50,
                s.callback_ms.p99, s.from_input_ms.p50, s.from_input_ms.p99, s.from_capture_ms.p50,
                s.from_capture_ms.p99);
  std::printf("    %-20s %-9s %5zu |                   |                   | %7.1f %7.1f ms\n",
              "end to end", "plan", t.end_to_end_ms.n, t.end_to_end_ms.p50, t.end_to_end_ms.p99);
}

std::optional<ImageSize> parse_size(const std::string& s) {
  unsigned w = 0, h = 0;
  char x = 0;
  if (std::sscanf(s.c_str(), "%u%c%u", &w, &x, &h) != 3 || x != 'x' || w < 16 || h < 16 ||
      w > 8192 || h > 8192)
    return std::nullopt;
  return ImageSize{.width = w, .height = h};
}

}  // namespace

int run_pipeline_bench(const PipelineBenchOptions& o) {
  std::vector<ImageSize> sizes;
  for (const std::string& s :
       o.sizes.empty() ? std::vector<std::string>{"320x256", "640x480"} : o.sizes) {
    auto size = parse_size(s);
    if (!size) {
      std::fprintf(stderr, "bench pipeline: image size '%s' is not WxH (16..8192 each)\n",
                   s.c_str());
      return 2;
    }
    sizes.push_back(*size);
  }
  if (!(o.nominal_rate_hz > 0) || o.threads == 0 || !(o.tolerance > 0)) {
    std::fprintf(stderr, "bench pipeline: the rate, threads and tolerance must be positive\n");
    return 2;
  }
  const uint32_t frames = o.frames > 0 ? o.frames : (o.quick ? 12 : 100);
  const int max_trials = o.max_trials > 0 ? o.max_trials : (o.quick ? 2 : 8);

  Json out;
  out["launch"] = o.launch_path;
  out["scene"] = o.scene_path;
  out["threads"] = o.threads;
  out["hardware_threads"] = std::thread::hardware_concurrency();
  out["pairs_per_trial"] = frames;
  out["warmup_pairs"] = kWarmupPairs;
  out["nominal_rate_hz"] = o.nominal_rate_hz;
  out["max_rate_method"] =
      "measured: the graph on the wall clock, pairs published at the rate whatever the graph "
      "does; sustained = every pair integrated into the map";
  out["load_avg_before"] = load_average();
  out["sizes"] = Json::array();
  for (const ImageSize& size : sizes) {
    std::fprintf(stderr, "bench pipeline: %ux%u: capturing %u stereo pairs\n", size.width,
                 size.height, frames);
    auto pairs = capture(o, size, frames);
    if (!pairs) {
      std::fprintf(stderr, "bench pipeline: %s\n", pairs.error().c_str());
      return 1;
    }
    std::vector<Trial> trials;
    const auto trial = [&](double rate) -> bool {
      auto t = run_trial(o, size, *pairs, rate);
      if (!t) {
        std::fprintf(stderr, "bench pipeline: %s\n", t.error().c_str());
        return false;
      }
      print_trial_line(*t);
      trials.push_back(std::move(t).value());
      return true;
    };
    {
      auto warmup =
          run_trial(o, size, std::span(*pairs).first(std::min<size_t>(kWarmupPairs, pairs->size())),
                    o.nominal_rate_hz);
      if (!warmup) {
        std::fprintf(stderr, "bench pipeline: %s\n", warmup.error().c_str());
        return 1;
      }
    }
    if (!trial(o.nominal_rate_hz)) return 1;
    // 3. the highest sustained rate: doubling, then bisection (geometric)
    double lo = trials.front().sustained() ? o.nominal_rate_hz : 0;
    double hi = trials.front().sustained() ? 0 : o.nominal_rate_hz;
    for (int k = 0; k < max_trials; ++k) {
      double rate = 0;
      if (hi == 0)
        rate = std::min(2 * lo, kMaxRateHz);
      else if (lo == 0)
        rate = hi / 2;
      else if (hi / lo <= 1 + o.tolerance)
        break;
      else
        rate = std::sqrt(lo * hi);
      if ((hi == 0 && lo >= kMaxRateHz) || (lo == 0 && rate < 0.1)) break;
      if (!trial(rate)) return 1;
      (trials.back().sustained() ? lo : hi) = rate;
    }
    const Trial* at_max = nullptr;
    for (const Trial& t : trials)
      if (t.sustained() && t.rate_hz == lo) at_max = &t;

    Json s{{"width", size.width},
           {"height", size.height},
           {"num_disparities", size.num_disparities()},
           {"nominal", to_json(trials.front())},
           {"max_rate_hz", lo},
           {"first_failing_rate_hz", hi > 0 ? Json(hi) : Json(nullptr)},
           {"at_max_rate", at_max != nullptr ? to_json(*at_max) : Json(nullptr)}};
    Json all = Json::array();
    for (const Trial& t : trials) all.push_back(to_json(t));
    s["trials"] = all;
    out["sizes"].push_back(s);

    if (!o.json) {
      std::printf("%u x %u (SGBM %u disparities, %zu executor threads, %u pairs per trial)\n",
                  size.width, size.height, size.num_disparities(), o.threads, frames);
      print_stages("nominal rate", trials.front());
      if (at_max != nullptr && at_max != &trials.front())
        print_stages("highest sustained", *at_max);
      std::printf("  highest sustained camera rate: %.2f Hz", lo);
      if (hi > 0)
        std::printf(" (%.2f Hz dropped frames)\n", hi);
      else
        std::printf(" (a lower bound: no failing rate found)\n");
    }
  }
  out["load_avg_after"] = load_average();
  if (o.json) std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace scancrew::bench
