// The path tracker's set-up on the sim backend (tracker_harness.hpp): the first scan (a turn
// on the spot before a ground robot drives), the example launch file, bad parameters.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "components/path_tracker/path_tracker.hpp"
#include "executors/launch.hpp"
#include "tests/components/path_tracker/tracker_harness.hpp"

namespace scancrew::path_tracker {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

TEST(PathTracker, AGroundRobotTurnsOnTheSpotFirstWhenAsked) {
  // a path straight ahead; the first scan turns a full circle before the robot drives
  const std::vector<Waypoint4> path = {{-3, -2, 0, 0}, {-1, -2, 0, 0}};
  const std::string player = "{waypoints: " + list(path) + "}";
  TrackerRun r = run(launch_text("ground", {-3, -2, 0, 0}, 25.0, player,
                                 "{initial_turn_deg: 360, ground_max_yaw_rate_radps: 0.5}", "{}"));
  ASSERT_NE(r.tracker, nullptr);
  ASSERT_FALSE(r.log->poses.empty());
  EXPECT_EQ(r.tracker->plans_done(), 1u);
  EXPECT_EQ(r.tracker->mode(), msg::RobotState::Mode::kDone);
  // turned on the spot (yaw accumulated from the truth) before it left its start
  double turned = 0, turned_when_left = -1;
  for (size_t i = 1; i < r.log->poses.size(); ++i) {
    turned +=
        std::abs(std::remainder(yaw_of(r.log->poses[i]) - yaw_of(r.log->poses[i - 1]), 2 * M_PI));
    if (turned_when_left < 0 && distance(r.log->poses[i], path.front(), true) > 0.05)
      turned_when_left = turned;
  }
  std::printf("[figures] first scan: turned %.0f deg before leaving the start, %.0f in all\n",
              turned_when_left * 180 / M_PI, turned * 180 / M_PI);
  EXPECT_GE(turned_when_left, 2 * M_PI - 0.05);
  for (const msg::VelocityCommand& c : r.log->commands) {
    if (t_s(c.header) >= 2 * M_PI / 0.5 - 0.5) continue;
    EXPECT_EQ(c.linear_mps.x, 0.0) << t_s(c.header);
    EXPECT_EQ(c.yaw_rate_radps, 0.5) << t_s(c.header);
  }
  EXPECT_LT(distance(r.log->poses.back(), path.back(), true), 0.1 + 1e-3);

  // the first scan is for ground robots: a multirotor flies its path at once
  TrackerRun air = run(launch_text("multirotor", {-3, -2, 1, 0}, 6.0,
                                   "{waypoints: [-3, -2, 1, 0, "
                                   "-1, -2, 1, 0]}",
                                   "{initial_turn_deg: 360}", "{}"));
  ASSERT_NE(air.tracker, nullptr);
  EXPECT_EQ(air.tracker->plans_done(), 1u);
}

TEST(PathTracker, TheExampleLaunchFileBringsBothRobotsToTheirGoals) {
  // launch_cfg/tracker_sim.yaml names its scene relative to the repository root
  const std::filesystem::path cwd = std::filesystem::current_path();
  std::filesystem::current_path(SCANCREW_SOURCE_DIR);
  auto launch = Launch::from_file("launch_cfg/tracker_sim.yaml");
  std::filesystem::current_path(cwd);
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  int trackers = 0;
  for (const auto& c : (*launch)->components()) {
    const auto* t = dynamic_cast<const PathTracker*>(c.get());
    if (t == nullptr) continue;
    ++trackers;
    EXPECT_EQ(t->plans_done(), 1u) << t->qualified_name();
    EXPECT_LE(t->done_position_error_m(), 0.1) << t->qualified_name();
    std::printf(
        "[figures] %s (%s): done at %.1f s, %.2f m travelled, %.3f m %.2f deg from the goal\n",
        t->qualified_name().c_str(), t->ground() ? "ground" : "multirotor",
        1e-9 * static_cast<double>(t->done_stamp_ns()), t->travelled_m(),
        t->done_position_error_m(), t->done_yaw_error_rad() * 180 / M_PI);
  }
  EXPECT_EQ(trackers, 2);
}

TEST(PathTracker, RefusesBadParameters) {
  const std::string path = "{waypoints: [0, 0, 0, 0]}";
  auto launch = Launch::from_string(
      launch_text("ground", {-3, -2, 0, 0}, 1.0, path, "{align_radius_m: 0.5}", "{}"), "bad.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("align_radius_m"), std::string::npos)
      << launch.error().front();
  launch = Launch::from_string(
      launch_text("ground", {-3, -2, 0, 0}, 1.0, "{waypoints: [1, 2, 3]}", "{}", "{}"), "bad.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("quadruples"), std::string::npos) << launch.error().front();
}

}  // namespace
}  // namespace scancrew::path_tracker
