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
#include "bench/pipeline/run_latency.hpp"

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

// The image sizes asked for (the defaults when none); nullopt (after a message) when one is
// not WxH.
std::optional<std::vector<ImageSize>> parse_sizes(const PipelineBenchOptions& o) {
  std::vector<ImageSize> sizes;
  for (const std::string& s :
       o.sizes.empty() ? std::vector<std::string>{"320x256", "640x480"} : o.sizes) {
    auto size = parse_size(s);
    if (!size) {
      std::fprintf(stderr, "bench pipeline: image size '%s' is not WxH (16..8192 each)\n",
                   s.c_str());
      return std::nullopt;
    }
    sizes.push_back(*size);
  }
  return sizes;
}

// The trials at one image size and the rate search's bounds.
struct RateSearch {
  std::vector<Trial> trials;  // the nominal rate's first
  double lo = 0;              // the highest sustained rate found
  double hi = 0;              // the lowest failing rate found; 0: none
};

// Runs one trial at rate, prints its line and appends it to trials; false (after a message)
// when it fails.
bool add_trial(const PipelineBenchOptions& o, const ImageSize& size,
               const std::vector<FrameCapture::Pair>& pairs, double rate,
               std::vector<Trial>& trials) {
  auto t = run_trial(o, size, pairs, rate);
  if (!t) {
    std::fprintf(stderr, "bench pipeline: %s\n", t.error().c_str());
    return false;
  }
  print_trial_line(*t);
  trials.push_back(std::move(t).value());
  return true;
}

// Runs the unreported warm-up trial, the nominal rate's trial and the search for the highest
// sustained rate; nullopt (after a message) when a trial fails.
std::optional<RateSearch> search_rates(const PipelineBenchOptions& o, const ImageSize& size,
                                       const std::vector<FrameCapture::Pair>& pairs,
                                       int max_trials) {
  RateSearch r;
  {
    auto warmup =
        run_trial(o, size, std::span(pairs).first(std::min<size_t>(kWarmupPairs, pairs.size())),
                  o.nominal_rate_hz);
    if (!warmup) {
      std::fprintf(stderr, "bench pipeline: %s\n", warmup.error().c_str());
      return std::nullopt;
    }
  }
  if (!add_trial(o, size, pairs, o.nominal_rate_hz, r.trials)) return std::nullopt;
  // 3. the highest sustained rate: doubling, then bisection (geometric)
  double lo = r.trials.front().sustained() ? o.nominal_rate_hz : 0;
  double hi = r.trials.front().sustained() ? 0 : o.nominal_rate_hz;
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
    if (!add_trial(o, size, pairs, rate, r.trials)) return std::nullopt;
    (r.trials.back().sustained() ? lo : hi) = rate;
  }
  r.lo = lo;
  r.hi = hi;
  return r;
}

// The size's entry in out["sizes"]: its nominal, highest sustained and every trial.
Json size_json(const ImageSize& size, const RateSearch& r, const Trial* at_max) {
  Json s{{"width", size.width},
         {"height", size.height},
         {"num_disparities", size.num_disparities()},
         {"nominal", to_json(r.trials.front())},
         {"max_rate_hz", r.lo},
         {"first_failing_rate_hz", r.hi > 0 ? Json(r.hi) : Json(nullptr)},
         {"at_max_rate", at_max != nullptr ? to_json(*at_max) : Json(nullptr)}};
  Json all = Json::array();
  for (const Trial& t : r.trials) all.push_back(to_json(t));
  s["trials"] = all;
  return s;
}

// Prints the size's stage tables and highest sustained rate as text.
void print_size(const PipelineBenchOptions& o, const ImageSize& size, uint32_t frames,
                const RateSearch& r, const Trial* at_max) {
  std::printf("%u x %u (SGBM %u disparities, %zu executor threads, %u pairs per trial)\n",
              size.width, size.height, size.num_disparities(), o.threads, frames);
  print_stages("nominal rate", r.trials.front());
  if (at_max != nullptr && at_max != &r.trials.front()) print_stages("highest sustained", *at_max);
  std::printf("  highest sustained camera rate: %.2f Hz", r.lo);
  if (r.hi > 0)
    std::printf(" (%.2f Hz dropped frames)\n", r.hi);
  else
    std::printf(" (a lower bound: no failing rate found)\n");
}

}  // namespace

int run_pipeline_bench(const PipelineBenchOptions& o) {
  if (!o.run_dir.empty()) return print_run_latency(o.run_dir, o.json);
  const auto sizes = parse_sizes(o);
  if (!sizes) return 2;
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
  for (const ImageSize& size : *sizes) {
    std::fprintf(stderr, "bench pipeline: %ux%u: capturing %u stereo pairs\n", size.width,
                 size.height, frames);
    auto pairs = capture(o, size, frames);
    if (!pairs) {
      std::fprintf(stderr, "bench pipeline: %s\n", pairs.error().c_str());
      return 1;
    }
    const auto search = search_rates(o, size, *pairs, max_trials);
    if (!search) return 1;
    const Trial* at_max = nullptr;
    for (const Trial& t : search->trials)
      if (t.sustained() && t.rate_hz == search->lo) at_max = &t;

    out["sizes"].push_back(size_json(size, *search, at_max));

    if (!o.json) print_size(o, size, frames, *search, at_max);
  }
  out["load_avg_after"] = load_average();
  if (o.json) std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace scancrew::bench
