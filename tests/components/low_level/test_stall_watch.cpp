// StallWatch (stall_watch.hpp): fires once the robot has stood still for timeout_s, not
// while it drives or turns on the spot, and starts again after a reset or a firing.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "components/low_level/stall_watch.hpp"

namespace scancrew::low_level {
namespace {

TEST(StallWatch, FiresOnceAfterTheTimeoutStandingStill) {
  StallWatch w({.timeout_s = 30.0, .min_motion_m = 0.1, .min_turn_deg = 10.0});
  const Eigen::Vector3d at(-8.28, 2.49, 0.0);
  int fired = 0;
  double first_s = -1;
  // 0.1 s ticks over 45 s, creeping 1 mm per second (below min_motion_m in 30 s)
  for (int k = 0; k <= 450; ++k) {
    const double t = 0.1 * k;
    if (w.update(at + Eigen::Vector3d(0.001 * t, 0, 0), 2.31, t)) {
      ++fired;
      if (first_s < 0) first_s = t;
    }
  }
  EXPECT_EQ(fired, 1);
  EXPECT_NEAR(first_s, 30.0, 1e-9);
}

TEST(StallWatch, DrivingOrTurningOnTheSpotIsMotion) {
  StallWatch drive({.timeout_s = 5.0});
  StallWatch turn({.timeout_s = 5.0});
  for (int k = 0; k <= 600; ++k) {
    const double t = 0.1 * k;
    EXPECT_FALSE(drive.update(Eigen::Vector3d(0.05 * t, 0, 0), 0.0, t)) << t;  // 5 cm/s
    EXPECT_FALSE(turn.update(Eigen::Vector3d::Zero(), 0.1 * t, t)) << t;       // 0.1 rad/s
  }
}

TEST(StallWatch, AResetStartsTheWatchAgainAndZeroNeverFires) {
  StallWatch w({.timeout_s = 10.0});
  for (int k = 0; k <= 90; ++k) EXPECT_FALSE(w.update(Eigen::Vector3d::Zero(), 0.0, 0.1 * k));
  EXPECT_NEAR(w.still_for_s(9.0), 9.0, 1e-9);
  w.reset();  // a new path at 9 s
  EXPECT_FALSE(w.update(Eigen::Vector3d::Zero(), 0.0, 9.5));
  EXPECT_FALSE(w.update(Eigen::Vector3d::Zero(), 0.0, 19.4));
  EXPECT_TRUE(w.update(Eigen::Vector3d::Zero(), 0.0, 19.5));
  StallWatch never({.timeout_s = 0.0});
  for (int k = 0; k <= 100; ++k) EXPECT_FALSE(never.update(Eigen::Vector3d::Zero(), 0.0, 10.0 * k));
}

TEST(StallWatch, ANanPoseIsNoMotion) {
  StallWatch w({.timeout_s = 1.0});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(w.update(Eigen::Vector3d::Zero(), 0.0, 0.0));
  EXPECT_FALSE(w.update(Eigen::Vector3d(nan, 0, 0), nan, 0.5));
  EXPECT_TRUE(w.update(Eigen::Vector3d(nan, 0, 0), nan, 1.0));
}

}  // namespace
}  // namespace scancrew::low_level
