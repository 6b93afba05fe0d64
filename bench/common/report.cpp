#include "bench/common/report.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "bench/bench_stats.hpp"

namespace scancrew::bench {

int finish_report(nlohmann::ordered_json& out, bool json, int failures,
                  void (*add_targets)(nlohmann::ordered_json&),
                  void (*print_table)(const nlohmann::ordered_json&)) {
  out["load_average_1min"].push_back(load_average());
  add_targets(out);
  if (json)
    std::printf("%s\n", out.dump().c_str());
  else
    print_table(out);
  return failures == 0 ? 0 : 1;
}

}  // namespace scancrew::bench
