// WheelBuffer (the VIO's wheel-odometry readings) and the simulator's WheelOdometry.

#include <gtest/gtest.h>

#include <cmath>

#include "components/team_simulator/wheel_odometry.hpp"
#include "components/vio/wheel_buffer.hpp"

namespace scancrew::vio {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(WheelBuffer, MeanVelocityHoldsEachReadingToTheNext) {
  WheelBuffer b;
  ASSERT_TRUE(b.add(0, {1, 0, 0}));
  ASSERT_TRUE(b.add(20 * kMs, {0.5, 0, 0}));
  ASSERT_TRUE(b.add(40 * kMs, {0, 0, 0}));
  EXPECT_FALSE(b.add(40 * kMs, {9, 9, 9}));  // not after the last: refused
  // [10, 50] ms: 10 ms at 1, 20 ms at 0.5, 10 ms at 0 -> 20 / 40 = 0.5
  const auto v = b.mean_velocity(10 * kMs, 50 * kMs);
  ASSERT_TRUE(v);
  EXPECT_NEAR(v->x(), 0.5, 1e-12);
  EXPECT_EQ(v->y(), 0);
}

TEST(WheelBuffer, NothingWhenTheBaseStoppedReportingOrHasNotStarted) {
  WheelBuffer b(100 * kMs);
  EXPECT_FALSE(b.mean_velocity(0, 50 * kMs));  // empty
  ASSERT_TRUE(b.add(0, {1, 0, 0}));
  EXPECT_TRUE(b.mean_velocity(0, 100 * kMs));
  EXPECT_FALSE(b.mean_velocity(200 * kMs, 300 * kMs));  // last reading 300 ms before t1
  WheelBuffer late(100 * kMs);
  ASSERT_TRUE(late.add(500 * kMs, {1, 0, 0}));
  EXPECT_FALSE(late.mean_velocity(0, 500 * kMs));  // first reading long after t0
}

TEST(WheelBuffer, DropBeforeKeepsTheReadingThatHoldsIntoTheNextInterval) {
  WheelBuffer b;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(b.add(i * 20 * kMs, {0.1 * i, 0, 0}));
  b.drop_before(100 * kMs);
  EXPECT_EQ(b.size(), 5u);  // 100 ms (holds from 100 on) to 180 ms
  const auto v = b.mean_velocity(100 * kMs, 120 * kMs);
  ASSERT_TRUE(v);
  EXPECT_NEAR(v->x(), 0.5, 1e-12);
}

TEST(WheelOdometry, ReportsTheBodyVelocityWithItsScaleAndDeadReckonsThePose) {
  const team_simulator::WheelOdometryConfig config{
      .rate_hz = 50, .scale_sigma = 0.02, .speed_noise_mps = 0, .yaw_rate_noise_radps = 0};
  msg::Pose3 start;
  start.position = {1, 2, 0};
  start.orientation = {std::cos(M_PI / 4), 0, 0, std::sin(M_PI / 4)};  // yaw 90 deg: north
  team_simulator::WheelOdometry w(config, 42, start);
  const double scale = w.scale();
  EXPECT_NE(scale, 1.0);
  EXPECT_NEAR(scale, 1.0, 0.1);
  // 10 s north at 0.5 m/s (world velocity along +y), readings every 20 ms
  msg::Odometry last;
  for (int i = 0; i <= 500; ++i) last = w.measure(i * 20 * kMs, {0, 0.5, 0}, M_PI / 2, 0);
  EXPECT_NEAR(last.linear_velocity_mps.x, 0.5 * scale, 1e-12);  // forward in the body frame
  EXPECT_NEAR(last.linear_velocity_mps.y, 0, 1e-12);
  EXPECT_NEAR(last.T_world_body.position.x, 1, 1e-9);
  EXPECT_NEAR(last.T_world_body.position.y, 2 + 5 * scale, 1e-9);
  // the same seed, the same stream
  team_simulator::WheelOdometry again(config, 42, start);
  EXPECT_EQ(again.scale(), scale);
}

}  // namespace
}  // namespace scancrew::vio
