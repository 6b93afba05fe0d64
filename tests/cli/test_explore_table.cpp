// bench explore's tables (cli/explore_table.hpp): metrics.json read into a run, the --quick
// check of a run's metrics, the Markdown rows per family x team x architecture.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli/explore_table.hpp"

namespace scancrew::cli {
namespace {

using enum Architecture;

// A metrics.json of a run with two robots whose time breakdowns sum to sim_time_s.
std::string metrics(const std::string& reason, double sim_s, double completion_s,
                    double breakdown_s, const std::string& compute = "charged") {
  const std::string time =
      "{\"driving\": " + std::to_string(breakdown_s - 10) + ", \"waiting\": 10, \"idle_open\": 0}";
  return "{\"stop_reason\": \"" + reason + "\", \"sim_time_s\": " + std::to_string(sim_s) +
         ", \"completion_time_s\": " +
         (completion_s > 0 ? std::to_string(completion_s) : std::string("null")) +
         ", \"wall_time_s\": 12, \"coverage\": 0.9, \"coverage_reachable\": 0.95, "
         "\"rmse_m\": 0.02, \"total_path_length_m\": 100, \"collisions\": 0, "
         "\"idle_share\": 0.1, \"compute_time\": \"" +
         compute +
         "\", \"time_to_coverage_reachable_s\": {\"50\": 10, \"90\": 40, \"95\": null}, "
         "\"places\": [{\"place\": \"r1\"}, {\"place\": \"r2\"}], \"robots\": [{\"time_s\": " +
         time + "}, {\"time_s\": " + time + "}]}";
}

ExploreRun planned(const std::string& family, size_t robots, Architecture arch) {
  return ExploreRun{.scene = family + "_1",
                    .family = family,
                    .kind = robot::RobotKind::kGround,
                    .arch = arch,
                    .robots = robots,
                    .budget_s = 600,
                    .exit_status = 0};
}

TEST(ExploreTable, ReadsTheMetricsOfARun) {
  auto r = read_explore_metrics(metrics("complete", 250, 250, 250),
                                planned("indoor", 2, kDistributed), "m");
  ASSERT_TRUE(r) << r.error();
  EXPECT_TRUE(r->completed());
  EXPECT_DOUBLE_EQ(r->completion_time_s, 250);
  EXPECT_DOUBLE_EQ(r->t90_reachable_s, 40);
  EXPECT_TRUE(std::isnan(r->t95_reachable_s));
  EXPECT_DOUBLE_EQ(r->coverage_reachable, 0.95);
  EXPECT_DOUBLE_EQ(r->breakdown_sum_s, 250);
  EXPECT_EQ(r->compute_time, "charged");
  EXPECT_EQ(r->places, (std::vector<std::string>{"r1", "r2"}));
  EXPECT_FALSE(read_explore_metrics("[1]", planned("indoor", 1, kSingle), "m"));
  EXPECT_FALSE(read_explore_metrics("{}", planned("indoor", 1, kSingle), "m"));
}

TEST(ExploreTable, TheQuickCheckFindsInconsistentMetrics) {
  auto ok = read_explore_metrics(metrics("time_budget", 150, -1, 150),
                                 planned("indoor", 1, kSingle), "m");
  ASSERT_TRUE(ok);
  EXPECT_EQ(check_explore_run(*ok), "");
  auto gap = read_explore_metrics(metrics("time_budget", 150, -1, 120),
                                  planned("indoor", 1, kSingle), "m");
  EXPECT_NE(check_explore_run(*gap).find("does not sum"), std::string::npos);
  auto free = read_explore_metrics(metrics("complete", 150, 150, 150, "free"),
                                   planned("indoor", 1, kSingle), "m");
  EXPECT_NE(check_explore_run(*free).find("not charged"), std::string::npos);
  ExploreRun on_station = *ok;
  on_station.places = {"r1", "station"};
  EXPECT_NE(check_explore_run(on_station).find("ground station"), std::string::npos);
  ExploreRun crashed = *ok;
  crashed.exit_status = 134;
  EXPECT_NE(check_explore_run(crashed).find("status 134"), std::string::npos);
  EXPECT_NE(check_explore_run(planned("indoor", 1, kSingle)).find("did not run"),
            std::string::npos);
}

TEST(ExploreTable, MarkdownHasARowPerFamilyTeamAndArchitecture) {
  std::vector<ExploreRun> runs;
  runs.push_back(*read_explore_metrics(metrics("complete", 200, 200, 200),
                                       planned("indoor", 2, kDistributed), "m"));
  runs.push_back(*read_explore_metrics(metrics("time_budget", 600, -1, 600),
                                       planned("indoor", 2, kDistributed), "m"));
  runs.push_back(planned("indoor", 4, kCentralized));  // failed: no metrics
  const std::string md = format_explore_markdown(runs, "t", "scancrew bench explore", "2 cores");
  EXPECT_NE(
      md.find("| indoor | 2 | distributed | 1/2 | ≥ 400.0 ± 282.8 | 40 ± 0 | — | 90.00 ± 0.00 | "
              "95.00 ± 0.00 | 20.0 ± 0.0 | 100.0 ± 0.0 | 0.0 ± 0.0 | 10 ± 0 |"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("| indoor | 4 | centralized | 0/1 (1 failed) |"), std::string::npos) << md;
  EXPECT_NE(md.find("Command: `scancrew bench explore`"), std::string::npos);
  const std::string csv = format_explore_csv(runs);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  // the kind, the architecture and the stop reason by their names
  EXPECT_NE(csv.find("\nindoor_1,indoor,ground,distributed,2,600,complete,0,200,"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\nindoor_1,indoor,ground,centralized,4,600,failed,0,"), std::string::npos)
      << csv;
  const std::string json = format_explore_json(runs);
  EXPECT_NE(json.find("\"kind\": \"ground\",\n      \"arch\": \"distributed\""), std::string::npos)
      << json;
  EXPECT_NE(json.find("\"stop_reason\": \"time_budget\""), std::string::npos) << json;
}

}  // namespace
}  // namespace scancrew::cli
