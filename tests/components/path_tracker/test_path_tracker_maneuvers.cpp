// The path tracker's maneuvers on the sim backend (tracker_harness.hpp): a stop maneuver
// zeroes the command at once and the robot stays put until resumed; a step-aside maneuver
// takes it to the aside pose, and it finishes the path after the resume.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/components/path_tracker/tracker_harness.hpp"

namespace scancrew::path_tracker {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

// A straight run along y = −2; a stop at 5 s, a resume at 10 s.
TEST(PathTracker, AStopManeuverZeroesTheCommandAtOnceAndHoldsUntilResumed) {
  for (const std::string kind : {"ground", "multirotor"}) {
    const std::vector<Waypoint4> path = {{-3, -2, 1, 0}, {3, -2, 1, 0}};
    TrackerRun r = run(launch_text(kind, {-3, -2, 1, 0}, 25.0, "{waypoints: " + list(path) + "}",
                                   "{}", "{maneuvers: [5.0, 1, 0, 0, 0, 0, 10.0, 0, 0, 0, 0, 0]}"));
    ASSERT_NE(r.tracker, nullptr);
    // the first command stamped at or after the stop is zero, and every one until the resume
    // (a tick in the same step as the order may come just before it, at the same stamp)
    const msg::VelocityCommand* at_order = nullptr;
    for (const msg::VelocityCommand& c : r.log->commands)
      if (std::abs(t_s(c.header) - 5.0) < 1e-6) at_order = &c;
    ASSERT_NE(at_order, nullptr);
    EXPECT_EQ(at_order->linear_mps.x, 0.0) << kind;  // sent with the order, not at the next tick
    bool seen = false;
    for (const msg::VelocityCommand& c : r.log->commands) {
      const double t = t_s(c.header);
      if (t < 5.0 + 1e-6) continue;
      if (t >= 10.0 - 1e-6) break;
      seen = true;
      EXPECT_EQ(c.linear_mps.x, 0.0) << kind;
      EXPECT_EQ(c.linear_mps.y, 0.0) << kind;
      EXPECT_EQ(c.linear_mps.z, 0.0) << kind;
      EXPECT_EQ(c.yaw_rate_radps, 0.0) << kind;
    }
    EXPECT_TRUE(seen);
    // moving at the stop; then within a few cm, and still
    const msg::Odometry* at_stop = nullptr;
    double max_drift_m = 0;
    for (const msg::Odometry& o : r.log->poses) {
      const double t = t_s(o.header);
      if (at_stop == nullptr && t >= 5.0 - 1e-6) at_stop = &o;
      if (at_stop != nullptr && t < 10.0 - 1e-6)
        max_drift_m = std::max(
            max_drift_m, std::hypot(o.T_world_body.position.x - at_stop->T_world_body.position.x,
                                    o.T_world_body.position.y - at_stop->T_world_body.position.y));
    }
    ASSERT_NE(at_stop, nullptr);
    EXPECT_GT(at_stop->T_world_body.position.x, -1.5) << kind;  // it was under way
    EXPECT_LT(max_drift_m, 0.05) << kind;
    bool stopped_reported = false;
    for (const msg::RobotState& s : r.log->states)
      if (t_s(s.header) > 5.5 && t_s(s.header) < 9.5)
        stopped_reported = stopped_reported || s.mode == msg::RobotState::Mode::kStopped;
    EXPECT_TRUE(stopped_reported) << kind;
    // after the resume it finishes the path
    EXPECT_EQ(r.tracker->plans_done(), 1u) << kind;
    EXPECT_LT(distance(r.log->poses.back(), path.back(), kind == "ground"), 0.1) << kind;
    std::printf("[figures] %s stop: drift after the stop %.3f m\n", kind.c_str(), max_drift_m);
  }
}

TEST(PathTracker, AStepAsideManeuverMovesTheRobotToTheAsidePoseThenItResumes) {
  for (const std::string kind : {"ground", "multirotor"}) {
    const std::vector<Waypoint4> path = {{-3, -2, 1, 0}, {3, -2, 1, 0}};
    const Waypoint4 aside = {-0.5, -1.0, 1.2, 90};
    TrackerRun r =
        run(launch_text(kind, {-3, -2, 1, 0}, 35.0, "{waypoints: " + list(path) + "}", "{}",
                        "{maneuvers: [4.0, 2, " + std::to_string(aside.x) + ", " +
                            std::to_string(aside.y) + ", " + std::to_string(aside.z) + ", " +
                            std::to_string(aside.yaw_deg) + ", 15.0, 0, 0, 0, 0, 0]}"));
    ASSERT_NE(r.tracker, nullptr);
    // at the aside pose before the resume, waiting there
    const msg::Odometry* before_resume = nullptr;
    for (const msg::Odometry& o : r.log->poses)
      if (t_s(o.header) < 15.0 - 1e-6) before_resume = &o;
    ASSERT_NE(before_resume, nullptr);
    const double aside_error_m = distance(*before_resume, aside, kind == "ground");
    EXPECT_LT(aside_error_m, 0.1) << kind;
    EXPECT_LT(yaw_error_deg(*before_resume, aside), 5.0) << kind;
    bool waiting = false;
    for (const msg::RobotState& s : r.log->states)
      if (t_s(s.header) > 14.0 && t_s(s.header) < 15.0 - 1e-6)
        waiting = s.mode == msg::RobotState::Mode::kWaiting;
    EXPECT_TRUE(waiting) << kind;
    EXPECT_EQ(r.tracker->plans_done(), 1u) << kind;
    EXPECT_LT(distance(r.log->poses.back(), path.back(), kind == "ground"), 0.1) << kind;
    std::printf("[figures] %s step aside: %.3f m, %.2f deg from the aside pose\n", kind.c_str(),
                aside_error_m, yaw_error_deg(*before_resume, aside));
  }
}

}  // namespace
}  // namespace scancrew::path_tracker
