// cli/thesis_table.hpp: the thesis's rows beside the bench's runs of its scenes.

#include <gtest/gtest.h>

#include <sstream>

#include "cli/thesis_table.hpp"

namespace scancrew::cli {
namespace {

using enum Architecture;
using enum StopReason;

ExploreRun run(const std::string& scene, size_t robots, Architecture arch, StopReason stop,
               double time_s) {
  ExploreRun r{.scene = scene, .family = scene, .arch = arch, .robots = robots};
  r.stop_reason = stop;
  r.sim_time_s = time_s;
  if (stop == kComplete) r.completion_time_s = time_s;
  r.coverage = 0.9123;
  r.coverage_reachable = 0.95;
  r.total_path_m = 812.5;
  return r;
}

std::string line_with(const std::string& md, const std::string& start) {
  std::istringstream in(md);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(start, 0) == 0) return line;
  return {};
}

TEST(ThesisTable, HoldsTheThesissRowsOfItsOwnScenes) {
  const auto& rows = thesis_results();
  ASSERT_EQ(rows.size(), 13u);
  // Table 4.2's dist-TSGA trio: 9'56'', 781 m, 95.9 %
  bool found = false;
  for (const ThesisResult& t : rows)
    if (t.scene == "powerplant" && t.robots == 3 && t.arch == kDistributed) {
      found = true;
      EXPECT_DOUBLE_EQ(t.time_s, 596);
      EXPECT_DOUBLE_EQ(t.total_path_m, 781);
      EXPECT_DOUBLE_EQ(t.coverage_pct, 95.9);
    }
  EXPECT_TRUE(found);
}

TEST(ThesisTable, SetsEachRunBesideItsThesisRow) {
  const std::vector<ExploreRun> runs = {
      run("powerplant", 3, kCentralized, kComplete, 558.0),
      run("powerplant", 3, kDistributed, kTimeBudget, 900.0),
      run("parking_lot", 4, kDistributed, kComplete, 400.0),  // not in the thesis
  };
  const std::string md = format_thesis_markdown(runs);
  EXPECT_EQ(line_with(md, "| powerplant | 3 | centralized |"),
            "| powerplant | 3 | centralized | 3.2 / 4.2 (TSGA) | 620 | 558.0 | 90 % | 91.0 | "
            "91.23 | 95.00 | 790.0 | 812.5 |");
  EXPECT_EQ(line_with(md, "| powerplant | 3 | distributed |"),
            "| powerplant | 3 | distributed | 4.2 (dist-TSGA) | 596 | ≥ 900.0 (out of time) | "
            "≥ 151 % | 95.9 | 91.23 | 95.00 | 781.0 | 812.5 |");
  EXPECT_EQ(
      line_with(md, "| powerplant | 5 | centralized |"),
      "| powerplant | 5 | centralized | 3.2 / 4.2 (TSGA) | 382 | not run | — | 90.6 | — | — | "
      "879.0 | — |");
  EXPECT_EQ(line_with(md, "| parking_lot | 4 | distributed |"), "");
}

}  // namespace
}  // namespace scancrew::cli
