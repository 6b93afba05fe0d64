// cli/sweep_table.hpp: metrics.json into runs, mean ± std, rows, time ratios, CSV, Markdown.

#include <gtest/gtest.h>

#include <sstream>

#include "cli/sweep_table.hpp"

namespace scancrew::cli {
namespace {

using enum Architecture;
using enum StopReason;

SweepRun measured(Architecture arch, size_t robots, int seed, StopReason stop, double time_s,
                  double coverage) {
  SweepRun r{.arch = arch, .robots = robots, .seed = seed};
  r.run_dir =
      "runs/sweep/" + to_string(arch) + "_r" + std::to_string(robots) + "_s" + std::to_string(seed);
  r.stop_reason = stop;
  r.scene = "launch_cfg/scenes/test_arena.yaml";
  r.sim_time_s = time_s;
  if (stop == kComplete) r.completion_time_s = time_s;
  r.wall_time_s = time_s / 10;
  r.coverage = coverage;
  r.mean_error_m = 0.001;
  r.rmse_m = 0.0075;
  r.total_path_length_m = 40.0 * static_cast<double>(robots);
  r.data_exchanged_bytes = arch == kDistributed ? 3.5e6 : 0.0;
  return r;
}

SweepRun failed(Architecture arch, size_t robots, int seed, const std::string& why) {
  SweepRun r{.arch = arch, .robots = robots, .seed = seed};
  r.error = why;
  return r;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(SweepTable, ReadsTheMetricsOfARunDirectory) {
  const std::string json = R"({"launch": "launch_cfg/explore_arena_team.yaml",
    "scene": "launch_cfg/scenes/test_arena.yaml", "architecture": "distributed",
    "completed": true, "stop_reason": "complete", "completion_time_s": 102.9,
    "sim_time_s": 103.0, "wall_time_s": 11.2, "coverage": 0.9932, "mean_error_m": 0.0012,
    "rmse_m": 0.0076, "total_path_length_m": 48.8, "data_exchanged_bytes": 3512345,
    "collisions": 2, "replans": 17, "robots": []})";
  auto run = read_sweep_metrics(json, {.arch = kDistributed, .robots = 2, .seed = 3}, "m.json");
  ASSERT_TRUE(run) << run.error();
  EXPECT_EQ(run->arch, kDistributed);
  EXPECT_EQ(run->robots, 2u);
  EXPECT_EQ(run->seed, 3);
  EXPECT_EQ(run->stop_reason, kComplete);
  EXPECT_EQ(run->scene, "launch_cfg/scenes/test_arena.yaml");
  EXPECT_DOUBLE_EQ(run->completion_time_s, 102.9);
  EXPECT_DOUBLE_EQ(run->sim_time_s, 103.0);
  EXPECT_DOUBLE_EQ(run->wall_time_s, 11.2);
  EXPECT_DOUBLE_EQ(run->coverage, 0.9932);
  EXPECT_DOUBLE_EQ(run->mean_error_m, 0.0012);
  EXPECT_DOUBLE_EQ(run->rmse_m, 0.0076);
  EXPECT_DOUBLE_EQ(run->total_path_length_m, 48.8);
  EXPECT_DOUBLE_EQ(run->data_exchanged_bytes, 3512345.0);
  EXPECT_EQ(run->collisions, 2u);
  EXPECT_EQ(run->replans, 17u);
  EXPECT_EQ(outcome_of(*run), RunOutcome::kComplete);
}

TEST(SweepTable, NullOrAbsentMetricsStayMissing) {
  auto run = read_sweep_metrics(
      R"({"stop_reason": "time_budget", "completion_time_s": null, "sim_time_s": 240,
          "coverage": null, "data_exchanged_bytes": null})",
      {.arch = kCentralized, .robots = 2, .seed = 1}, "m.json");
  ASSERT_TRUE(run) << run.error();
  EXPECT_EQ(run->stop_reason, kTimeBudget);
  EXPECT_EQ(outcome_of(*run), RunOutcome::kIncomplete);
  EXPECT_TRUE(std::isnan(run->completion_time_s));
  EXPECT_DOUBLE_EQ(run->sim_time_s, 240.0);
  EXPECT_TRUE(std::isnan(run->coverage));
  EXPECT_TRUE(std::isnan(run->data_exchanged_bytes));
  EXPECT_TRUE(std::isnan(run->rmse_m));
  EXPECT_EQ(run->collisions, 0u);
}

TEST(SweepTable, RefusesTextThatIsNoMetricsObject) {
  auto not_json = read_sweep_metrics("{\"stop_reason\": ", {}, "runs/x/metrics.json");
  ASSERT_FALSE(not_json);
  EXPECT_EQ(not_json.error(), "runs/x/metrics.json: not a JSON object");
  auto array = read_sweep_metrics("[1, 2]", {}, "m.json");
  ASSERT_FALSE(array);
  EXPECT_EQ(array.error(), "m.json: not a JSON object");
  auto no_reason = read_sweep_metrics(R"({"sim_time_s": 3})", {}, "m.json");
  ASSERT_FALSE(no_reason);
  EXPECT_EQ(no_reason.error(), "m.json: no stop_reason");
  auto unknown = read_sweep_metrics(R"({"stop_reason": "exploded"})", {}, "m.json");
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error(),
            "m.json: stop_reason 'exploded' is not allowed; allowed: complete, stalled, "
            "time_budget, interrupted, failed");
}

TEST(SweepTable, OutcomesSortTheStopReasons) {
  SweepRun r;
  EXPECT_EQ(outcome_of(r), RunOutcome::kFailed);  // no metrics read
  r.stop_reason = kComplete;
  EXPECT_EQ(outcome_of(r), RunOutcome::kComplete);
  r.stop_reason = kStalled;
  EXPECT_EQ(outcome_of(r), RunOutcome::kIncomplete);
  r.stop_reason = kTimeBudget;
  EXPECT_EQ(outcome_of(r), RunOutcome::kIncomplete);
  r.stop_reason = kInterrupted;
  EXPECT_EQ(outcome_of(r), RunOutcome::kInterrupted);
}

TEST(SweepTable, MeanAndSampleStdOfTheFiniteValues) {
  const MeanStd s = mean_std({2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0});
  EXPECT_EQ(s.n, 8u);
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_NEAR(s.std, std::sqrt(32.0 / 7.0), 1e-12);  // n - 1
  const MeanStd one = mean_std({3.5, NAN});
  EXPECT_EQ(one.n, 1u);
  EXPECT_DOUBLE_EQ(one.mean, 3.5);
  EXPECT_DOUBLE_EQ(one.std, 0.0);
  const MeanStd none = mean_std({NAN, INFINITY});
  EXPECT_EQ(none.n, 0u);
  EXPECT_TRUE(std::isnan(none.mean));
  EXPECT_EQ(mean_std({}).n, 0u);
}

TEST(SweepTable, FormatsMeanAndStd) {
  EXPECT_EQ(format_mean_std(mean_std({100.0, 104.0}), 1), "102.0 ± 2.8");
  EXPECT_EQ(format_mean_std(mean_std({99.316}), 2), "99.32");  // one value: the mean alone
  EXPECT_EQ(format_mean_std(mean_std({}), 1), "—");
}

TEST(SweepTable, RowsAggregateTheSeedsOfEachArchitectureAndTeam) {
  const std::vector<SweepRun> runs = {
      measured(kSingle, 1, 1, kTimeBudget, 240.0, 0.983),
      measured(kSingle, 1, 2, kComplete, 220.0, 0.990),
      measured(kDistributed, 2, 1, kComplete, 100.0, 0.993),
      measured(kDistributed, 2, 2, kComplete, 110.0, 0.995),
      failed(kDistributed, 2, 3, "scancrew run exited with status 2"),
      measured(kDistributed, 2, 4, kInterrupted, 30.0, 0.4),
  };
  const auto rows = aggregate_sweep(runs);
  ASSERT_EQ(rows.size(), 2u);
  const SweepRow& single = rows[0];
  EXPECT_EQ(single.arch, kSingle);
  EXPECT_EQ(single.robots, 1u);
  EXPECT_EQ(single.runs, 2u);
  EXPECT_EQ(single.completed, 1u);
  EXPECT_EQ(single.incomplete, 1u);
  EXPECT_TRUE(single.time_is_lower_bound);  // the time-budget run counts its 240 s
  EXPECT_DOUBLE_EQ(single.time_s.mean, 230.0);
  EXPECT_EQ(single.time_s.n, 2u);
  EXPECT_NEAR(single.coverage_pct.mean, 98.65, 1e-9);
  EXPECT_NEAR(single.rmse_mm.mean, 7.5, 1e-9);

  const SweepRow& team = rows[1];
  EXPECT_EQ(team.arch, kDistributed);
  EXPECT_EQ(team.robots, 2u);
  EXPECT_EQ(team.scene, "launch_cfg/scenes/test_arena.yaml");  // the failed run's too
  EXPECT_EQ(team.runs, 4u);
  EXPECT_EQ(team.completed, 2u);
  EXPECT_EQ(team.failed, 1u);
  EXPECT_EQ(team.interrupted, 1u);
  EXPECT_FALSE(team.time_is_lower_bound);
  // failed and interrupted runs are in no statistic
  EXPECT_EQ(team.time_s.n, 2u);
  EXPECT_DOUBLE_EQ(team.time_s.mean, 105.0);
  EXPECT_NEAR(team.time_s.std, std::sqrt(50.0), 1e-12);
  EXPECT_NEAR(team.coverage_pct.mean, 99.4, 1e-9);
  EXPECT_NEAR(team.data_mb.mean, 3.5, 1e-12);
  EXPECT_NEAR(team.path_m.mean, 80.0, 1e-12);
}

TEST(SweepTable, CollisionsAreSummedOverTheRuns) {
  std::vector<SweepRun> runs = {measured(kDistributed, 3, 1, kComplete, 90, 0.99),
                                measured(kDistributed, 3, 2, kComplete, 95, 0.99)};
  runs[0].collisions = 2;
  runs[1].collisions = 1;
  EXPECT_EQ(aggregate_sweep(runs).front().collisions, 3u);
}

TEST(SweepTable, TimeRatioSaysWhichSideIsABound) {
  SweepRow ref{.time_s = mean_std({200.0})};
  SweepRow row{.time_s = mean_std({80.0})};
  TimeRatio r = time_ratio(row, ref);
  EXPECT_EQ(r.bound, TimeRatio::Bound::kExact);
  EXPECT_DOUBLE_EQ(r.percent, 40.0);
  ref.time_is_lower_bound = true;  // the single robot ran out of time: at most 40 %
  r = time_ratio(row, ref);
  EXPECT_EQ(r.bound, TimeRatio::Bound::kAtMost);
  EXPECT_DOUBLE_EQ(r.percent, 40.0);
  row.time_is_lower_bound = true;  // both bounds: nothing can be said
  EXPECT_EQ(time_ratio(row, ref).bound, TimeRatio::Bound::kUnknown);
  ref.time_is_lower_bound = false;
  EXPECT_EQ(time_ratio(row, ref).bound, TimeRatio::Bound::kAtLeast);
  EXPECT_EQ(time_ratio(SweepRow{}, ref).bound, TimeRatio::Bound::kUnknown);  // no time
}

TEST(SweepTable, CsvHasARowPerRunWithEmptyFieldsForMissingValues) {
  std::vector<SweepRun> runs = {measured(kDistributed, 2, 1, kComplete, 102.5, 0.9932),
                                failed(kSingle, 1, 1, "exited with status 2, see above")};
  const auto lines = lines_of(format_sweep_csv(runs));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0],
            "arch,robots,seed,stop_reason,completion_time_s,sim_time_s,wall_time_s,coverage,"
            "mean_error_m,rmse_m,total_path_length_m,data_exchanged_bytes,collisions,replans,"
            "coverage_reachable,idle_share,time_to_95_reachable_s,tours_per_goal,m_per_goal,"
            "share_driving,share_turning,share_traffic,share_waiting,share_backing_off,"
            "share_idle_open,share_idle_done,share_lost,compute_time,scene,run_dir,error");
  EXPECT_EQ(lines[1],
            "distributed,2,1,complete,102.5,102.5,10.25,0.9932,0.001,0.0075,80,3500000,0,0,,,,,,,,,"
            ",,,,,,launch_cfg/scenes/test_arena.yaml,runs/sweep/distributed_r2_s1,");
  EXPECT_EQ(lines[2],
            "single,1,1,failed,,,,,,,,,,,,,,,,,,,,,,,,,,,\"exited with status 2, see above\"");
}

TEST(SweepTable, MarkdownHasATableRowPerArchitectureAndTeam) {
  const std::vector<SweepRun> runs = {
      measured(kSingle, 1, 1, kTimeBudget, 240.0, 0.983),
      measured(kSingle, 1, 2, kTimeBudget, 240.0, 0.985),
      measured(kDistributed, 2, 1, kComplete, 100.0, 0.993),
      measured(kDistributed, 2, 2, kComplete, 106.0, 0.995),
      measured(kDistributed, 4, 1, kComplete, 70.0, 0.990),
      failed(kDistributed, 4, 2, "exited with status 2"),
  };
  const std::string md = format_sweep_markdown(runs, "Sweep of arena.sweep.yaml: 2 seeds");
  const auto lines = lines_of(md);
  ASSERT_GE(lines.size(), 9u);
  EXPECT_EQ(lines[0], "# Sweep of arena.sweep.yaml: 2 seeds");
  EXPECT_EQ(lines[2], "## Scene `launch_cfg/scenes/test_arena.yaml`");
  EXPECT_EQ(lines[4],
            "| architecture | robots | completed / runs | time (s) | time vs 1 robot | "
            "coverage (%) | reachable (%) | 95 % reachable (s) | RMSE (mm) | total path (m) | "
            "data exchanged (MB) | tours / goal | m / goal | time: drive / turn / traffic / wait / "
            "back off / idle open / idle done / lost (%) | collisions |");
  EXPECT_EQ(lines[6],
            "| single | 1 | 0/2 | ≥ 240.0 ± 0.0 | ref. | 98.40 ± 0.14 | — | — | 7.5 ± 0.0 | "
            "40.0 ± 0.0 | 0.00 ± 0.00 | — | — | — | 0 |");
  // the single robot ran out of time: the team needs at most 42.9 % of its time
  EXPECT_EQ(lines[7],
            "| distributed | 2 | 2/2 | 103.0 ± 4.2 | ≤ 43 % | 99.40 ± 0.14 | — | — | 7.5 ± 0.0 | "
            "80.0 ± 0.0 | 3.50 ± 0.00 | — | — | — | 0 |");
  EXPECT_EQ(lines[8],
            "| distributed | 4 | 1/2 (1 failed) | 70.0 | ≤ 29 % | 99.00 | — | — | 7.5 | 160.0 | "
            "3.50 | — | — | — | 0 |");
  EXPECT_NE(md.find("\n≥: a run of the row did not complete"), std::string::npos);
  EXPECT_NE(md.find("Failed runs (no metrics.json) and interrupted runs"), std::string::npos);
}

TEST(SweepTable, WhereTheTimeGoesIsReadAndAveragedOverTheRuns) {
  auto run = read_sweep_metrics(
      R"({"stop_reason": "complete", "completion_time_s": 100, "sim_time_s": 100,
          "coverage": 0.99, "tours_per_goal": 2.5, "m_per_goal": 4.0,
          "time_to_coverage_reachable_s": {"50": 20, "90": 60, "95": 80},
          "time_share": {"driving": 0.7, "turning": 0.1, "traffic": 0.05, "waiting": 0.05,
                         "backing_off": 0.0, "idle_open": 0.1, "idle_done": 0.0, "lost": 0.0}})",
      {.arch = kCentralized, .robots = 2, .seed = 1}, "m.json");
  ASSERT_TRUE(run) << run.error();
  EXPECT_DOUBLE_EQ(run->m_per_goal, 4.0);
  EXPECT_DOUBLE_EQ(run->time_share[static_cast<size_t>(report::Activity::kTraffic)], 0.05);
  EXPECT_DOUBLE_EQ(run->time_share[static_cast<size_t>(report::Activity::kIdleOpen)], 0.1);
  SweepRun other = *run;
  other.seed = 2;
  other.time_share[static_cast<size_t>(report::Activity::kDriving)] = 0.5;
  other.time_share[static_cast<size_t>(report::Activity::kIdleOpen)] = 0.3;
  other.tours_per_goal = 3.5;
  other.time_to_95_reachable_s = 100;
  const std::vector<SweepRun> runs = {*run, other};
  const auto rows = aggregate_sweep(runs);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_DOUBLE_EQ(rows[0].time_share_pct[0].mean, 60.0);
  EXPECT_DOUBLE_EQ(rows[0].tours_per_goal.mean, 3.0);
  EXPECT_DOUBLE_EQ(rows[0].t95_reachable_s.mean, 90.0);
  const auto lines = lines_of(format_sweep_markdown(runs, "t"));
  ASSERT_GE(lines.size(), 7u);
  EXPECT_NE(lines[6].find("| 90 ± 14 |"), std::string::npos) << lines[6];
  EXPECT_NE(lines[6].find("| 3.0 ± 0.7 | 4.0 ± 0.0 | 60 / 10 / 5 / 5 / 0 / 20 / 0 / 0 | 0 |"),
            std::string::npos)
      << lines[6];
}

TEST(SweepTable, WithoutASingleRowTheTeamOfOneIsTheReference) {
  const std::vector<SweepRun> runs = {measured(kDistributed, 1, 1, kComplete, 200.0, 0.99),
                                      measured(kDistributed, 2, 1, kComplete, 100.0, 0.99)};
  const auto lines = lines_of(format_sweep_markdown(runs, "t"));
  ASSERT_GE(lines.size(), 8u);
  EXPECT_NE(lines[6].find("| distributed | 1 | 1/1 | 200.0 | ref. |"), std::string::npos);
  EXPECT_NE(lines[7].find("| distributed | 2 | 1/1 | 100.0 | 50 % |"), std::string::npos);
  // all complete: no note on lower bounds, none on failures
  const std::string md = format_sweep_markdown(runs, "t");
  EXPECT_EQ(md.find("≥:"), std::string::npos);
  EXPECT_EQ(md.find("Failed runs"), std::string::npos);
}

TEST(SweepTable, EachSceneHasItsOwnTable) {
  std::vector<SweepRun> runs = {measured(kSingle, 1, 1, kComplete, 200.0, 0.99),
                                measured(kSingle, 1, 1, kComplete, 800.0, 0.97)};
  runs[1].scene = "launch_cfg/scenes/parking_lot.yaml";
  const std::string md = format_sweep_markdown(runs, "t");
  const auto arena = md.find("## Scene `launch_cfg/scenes/test_arena.yaml`");
  const auto lot = md.find("## Scene `launch_cfg/scenes/parking_lot.yaml`");
  ASSERT_NE(arena, std::string::npos);
  ASSERT_NE(lot, std::string::npos);
  EXPECT_LT(arena, lot);
  EXPECT_NE(md.find("| single | 1 | 1/1 | 800.0 | ref. | 97.00 |"), std::string::npos);
}

}  // namespace
}  // namespace scancrew::cli
