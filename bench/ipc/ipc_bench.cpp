#include "bench/ipc/ipc_bench.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace scancrew::bench {

namespace {

const IpcResult* find(const std::vector<IpcResult>& results, const std::string& system,
                      const std::string& mode, size_t payload) {
  for (const IpcResult& r : results)
    if (r.system == system && r.mode == mode && r.payload_bytes == payload) return &r;
  return nullptr;
}

// The step-1 targets, judged on this run's figures (docs/bench_ipc.md).
void print_targets(const std::vector<IpcResult>& results) {
  std::printf("\ntargets:\n");
  for (const char* mode : {"same_thread", "cross_thread"}) {
    double lo = 1e300, hi = 0;
    for (const IpcResult& r : results)
      if (r.system == "scancrew" && r.mode == mode)
        lo = std::min(lo, r.p50_us), hi = std::max(hi, r.p50_us);
    if (hi > 0)
      std::printf("  scancrew %-12s p50 flat within 2x over payloads: %s (max/min %.2f)\n", mode,
                  hi / lo <= 2.0 ? "met" : "MISSED", hi / lo);
    const IpcResult* ours = find(results, "scancrew", mode, 1 << 20);
    const IpcResult* peer = find(results, "fastdds", mode, 1 << 20);
    if (ours && peer && ours->p50_us > 0)
      std::printf("  %-21s 1 MB p50 >= 10x lower than Fast DDS: %s (%.1fx)\n", mode,
                  peer->p50_us / ours->p50_us >= 10 ? "met" : "MISSED",
                  peer->p50_us / ours->p50_us);
    const IpcResult* iceoryx = find(results, "iceoryx", mode, 1 << 20);
    if (ours && iceoryx && ours->p50_us > 0)
      std::printf("  %-21s 1 MB p50 iceoryx / scancrew (information, no target): %.1fx\n", mode,
                  iceoryx->p50_us / ours->p50_us);
  }
  double worst = 0;
  for (const IpcResult& r : results)
    if (r.system == "scancrew" && r.mode == "cross_thread") worst = std::max(worst, r.p50_us);
  std::printf("  cross-thread p50 <= 10 us at every payload: %s (worst %.2f us)\n",
              worst <= 10 ? "met" : "MISSED", worst);
}

}  // namespace

int run_ipc_bench(const IpcOptions& options) {
  if (!options.json)
    std::fprintf(stderr, "bench ipc: %d messages per case, %d us apart (cross thread)\n",
                 options.samples, options.gap_us);
  // an unrecorded pass first: thread start-up, page faults and CPU clocks settle
  IpcOptions warm = options;
  warm.samples = 200;
  warm.payload_bytes = {64};
  (void)bench_scancrew(warm);
  std::vector<IpcResult> results = bench_scancrew(options);
  std::vector<IpcResult> fastdds = bench_fastdds(options);
  results.insert(results.end(), fastdds.begin(), fastdds.end());
  std::vector<IpcResult> iceoryx = bench_iceoryx(options);
  results.insert(results.end(), iceoryx.begin(), iceoryx.end());

  if (options.json) {
    nlohmann::json out;
    out["results"] = nlohmann::json::array();
    for (const IpcResult& r : results)
      out["results"].push_back({{"system", r.system},
                                {"mode", r.mode},
                                {"payload_bytes", r.payload_bytes},
                                {"p50_us", r.p50_us},
                                {"p99_us", r.p99_us},
                                {"max_us", r.max_us},
                                {"lost", r.lost},
                                {"spin_us", r.spin_us}});
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("%-9s %-12s %10s %10s %10s %10s %6s\n", "system", "mode", "payload_B", "p50_us",
                "p99_us", "max_us", "lost");
    for (const IpcResult& r : results)
      std::printf("%-9s %-12s %10zu %10.2f %10.2f %10.2f %6zu\n", r.system.c_str(), r.mode.c_str(),
                  r.payload_bytes, r.p50_us, r.p99_us, r.max_us, r.lost);
  }
  if (!options.json) print_targets(results);
  size_t lost = 0;
  for (const IpcResult& r : results) lost += r.lost;
  return lost == 0 ? 0 : 1;
}

}  // namespace scancrew::bench
