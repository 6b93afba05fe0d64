// The run-directory readers of `scancrew report` and the benchmark tables
// (report/run_files.hpp, cli/explore_table.hpp): byte 0 picks paths.csv, coverage.csv or
// metrics.json.
#include <string_view>

#include "cli/explore_table.hpp"
#include "fuzz/fuzz_input.hpp"
#include "report/run_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const uint8_t* rest = data + 1;
  const size_t n = size - 1;
  switch (data[0] % 3) {
    case 0:
      (void)scancrew::report::read_paths_csv(scancrew::fuzz::as_file(rest, n));
      break;
    case 1:
      (void)scancrew::report::read_coverage_csv(scancrew::fuzz::as_file(rest, n));
      break;
    default:
      (void)scancrew::cli::read_explore_metrics(
          std::string_view(reinterpret_cast<const char*>(rest), n), {}, "metrics.json");
  }
  return 0;
}
