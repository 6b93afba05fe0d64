// The path tracker's latency figures on the sim backend (tracker_harness.hpp), on sim time:
// the age of the pose behind each command, and camera to command (the first command after
// each new pose), as summarize() reports them for metrics.json.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/components/path_tracker/tracker_harness.hpp"

namespace scancrew::path_tracker {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

TEST(PathTracker, ReportsTheAgeOfThePoseBehindItsCommands) {
  // poses at the camera's 5 Hz, commands at 20 Hz, for 4 s
  const std::vector<Waypoint4> path = {{-3, -2, 0, 0}, {3, -2, 0, 0}};
  TrackerRun r = run(
      launch_text("ground", {-3, -2, 0, 0}, 4.0, "{waypoints: " + list(path) + "}", "{}", "{}"));
  ASSERT_NE(r.tracker, nullptr);
  const RunSummary summary = r.launch->summary();
  ASSERT_EQ(summary.command_latency.count(1), 1u);
  const RunSummary::CommandLatency& l = summary.command_latency.at(1);
  // every command after the first pose used a fresh pose; every pose was used
  EXPECT_GE(l.commands, 75u);
  EXPECT_LE(l.commands, 81u);
  EXPECT_GE(l.poses, 19u);
  EXPECT_LE(l.poses, 20u);
  EXPECT_EQ(l.poses, r.tracker->first_use_age().count());
  // camera to command: the next tracker tick, within its 50 ms period
  EXPECT_GT(l.first_use_p50_ms, 0.0);
  EXPECT_LE(l.first_use_max_ms, 50.0);
  // any command: the pose is at most a camera period and a tracker period old
  EXPECT_GT(l.age_p50_ms, l.first_use_p50_ms);
  EXPECT_LE(l.age_max_ms, 250.0);
  EXPECT_GE(l.age_max_ms, 150.0);
  EXPECT_LE(l.age_p99_ms, l.age_max_ms);
}

}  // namespace
}  // namespace scancrew::path_tracker
