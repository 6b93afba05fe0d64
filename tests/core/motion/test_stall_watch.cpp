// StallWatch (stall_watch.hpp): fires once the way left along the path has not shrunk for
// timeout_s, whether the robot stands still or rocks to and fro, not while it closes in;
// starts again after a reset or a firing. remaining_length_m: the way left from a position.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/motion/stall_watch.hpp"

namespace scancrew::motion {
namespace {

TEST(StallWatch, FiresOnceAfterTheTimeoutWithoutProgress) {
  StallWatch w({.timeout_s = 30.0, .min_progress_m = 0.1});
  int fired = 0;
  double first_s = -1;
  // 0.1 s ticks over 45 s, closing in by 3 mm per second (below min_progress_m in 30 s)
  for (int k = 0; k <= 450; ++k) {
    const double t = 0.1 * k;
    if (w.update(1.36 - 0.003 * t, t)) {
      ++fired;
      if (first_s < 0) first_s = t;
    }
  }
  EXPECT_EQ(fired, 1);
  EXPECT_NEAR(first_s, 30.0, 1e-9);
}

TEST(StallWatch, ClosingInIsProgressRockingToAndFroIsNot) {
  StallWatch closing({.timeout_s = 5.0});
  StallWatch rocking({.timeout_s = 5.0});
  bool rocking_fired = false;
  for (int k = 0; k <= 600; ++k) {
    const double t = 0.1 * k;
    EXPECT_FALSE(closing.update(40.0 - 0.05 * t, t)) << t;  // 5 cm/s
    // ±0.3 m about 2 m left, a swing every 4 s: moving all the time, getting nowhere
    rocking_fired = rocking.update(2.0 + 0.3 * std::sin(M_PI * t / 2), t) || rocking_fired;
  }
  EXPECT_TRUE(rocking_fired);
}

TEST(StallWatch, AResetStartsTheWatchAgainAndZeroNeverFires) {
  StallWatch w({.timeout_s = 10.0});
  for (int k = 0; k <= 90; ++k) EXPECT_FALSE(w.update(1.0, 0.1 * k));
  EXPECT_NEAR(w.stalled_for_s(9.0), 9.0, 1e-9);
  w.reset();  // a new path at 9 s
  EXPECT_FALSE(w.update(1.0, 9.5));
  EXPECT_FALSE(w.update(1.0, 19.4));
  EXPECT_TRUE(w.update(1.0, 19.5));
  StallWatch never({.timeout_s = 0.0});
  for (int k = 0; k <= 100; ++k) EXPECT_FALSE(never.update(1.0, 10.0 * k));
}

TEST(StallWatch, ANanIsNoProgress) {
  StallWatch w({.timeout_s = 1.0});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(w.update(1.0, 0.0));
  EXPECT_FALSE(w.update(nan, 0.5));
  EXPECT_TRUE(w.update(nan, 1.0));
}

msg::Waypoint wp(double x, double y, double z) {
  msg::Waypoint w;
  w.position = {x, y, z};
  return w;
}

// The path the parking lot's single robot (seed 5) stood on: 0.26 m out, back past the
// start to the goal; the goals carry the camera's height (0.35 m), the robot z = 0.
TEST(StallWatch, TheWayLeftRunsFromTheNearestSegmentInThePlaneForAGroundRobot) {
  const std::vector<msg::Waypoint> path{wp(-8.270, 2.493, 0.35), wp(-8.188, 2.246, 0.35),
                                        wp(-8.930, 3.060, 0.35)};
  const double leg1 = std::hypot(0.082, 0.247);
  const double leg2 = std::hypot(0.742, 0.814);
  const Eigen::Vector3d robot(-8.283, 2.489, 0.0);
  EXPECT_NEAR(remaining_length_m(path, robot, true),
              std::hypot(-8.188 + 8.283, 2.246 - 2.489) + leg2, 1e-9);
  // on the second leg, half-way: half of it left
  const Eigen::Vector3d half(-8.559, 2.653, 0.35);
  EXPECT_NEAR(remaining_length_m(path, half, false), 0.5 * leg2, 1e-3);
  EXPECT_GT(remaining_length_m(path, robot, false), remaining_length_m(path, robot, true));
  EXPECT_DOUBLE_EQ(remaining_length_m({}, robot, true), 0.0);
  EXPECT_NEAR(remaining_length_m(path, Eigen::Vector3d(-8.270, 2.493, 0.0), true), leg1 + leg2,
              1e-9);
}

}  // namespace
}  // namespace scancrew::motion
