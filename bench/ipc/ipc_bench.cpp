#include "bench/ipc/ipc_bench.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

namespace scancrew::bench {

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
                                {"lost", r.lost}});
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("%-9s %-12s %10s %10s %10s %10s %6s\n", "system", "mode", "payload_B", "p50_us",
                "p99_us", "max_us", "lost");
    for (const IpcResult& r : results)
      std::printf("%-9s %-12s %10zu %10.2f %10.2f %10.2f %6zu\n", r.system.c_str(), r.mode.c_str(),
                  r.payload_bytes, r.p50_us, r.p99_us, r.max_us, r.lost);
  }
  size_t lost = 0;
  for (const IpcResult& r : results) lost += r.lost;
  return lost == 0 ? 0 : 1;
}

}  // namespace scancrew::bench
