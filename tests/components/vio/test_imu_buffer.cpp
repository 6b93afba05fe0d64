// The gyro prior and the gravity alignment of the VIO.

#include <gtest/gtest.h>

#include <cmath>

#include "components/vio/imu_buffer.hpp"

namespace scancrew::vio {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(ImuBuffer, IntegratesAConstantRateBetweenTwoStamps) {
  ImuBuffer imu;
  const Eigen::Vector3d up(0, 0, 9.81), rate(0.1, -0.2, 0.5);
  for (int64_t t = 0; t <= 1000 * kMs; t += 10 * kMs) ASSERT_TRUE(imu.add(t, up, rate));
  const auto q = imu.rotation(200 * kMs, 700 * kMs);
  ASSERT_TRUE(q);
  const Eigen::AngleAxisd expected(rate.norm() * 0.5, rate.normalized());
  EXPECT_NEAR(q->angularDistance(Eigen::Quaterniond(expected)), 0, 1e-9);
  // stamps between samples: the rate holds from one sample to the next
  const auto part = imu.rotation(205 * kMs, 212 * kMs);
  ASSERT_TRUE(part);
  EXPECT_NEAR(Eigen::AngleAxisd(*part).angle(), rate.norm() * 0.007, 1e-9);
}

TEST(ImuBuffer, RefusesStampsGoingBackAndGapsItCannotBridge) {
  ImuBuffer imu(50 * kMs);
  const Eigen::Vector3d up(0, 0, 9.81), zero = Eigen::Vector3d::Zero();
  ASSERT_TRUE(imu.add(100 * kMs, up, zero));
  EXPECT_FALSE(imu.add(100 * kMs, up, zero));
  EXPECT_FALSE(imu.add(90 * kMs, up, zero));
  EXPECT_TRUE(imu.rotation(90 * kMs, 140 * kMs));   // 40 ms held past the last sample
  EXPECT_FALSE(imu.rotation(90 * kMs, 200 * kMs));  // the IMU went quiet
  EXPECT_FALSE(imu.rotation(10 * kMs, 100 * kMs));  // it had not started
  ASSERT_TRUE(imu.add(300 * kMs, up, zero));
  EXPECT_FALSE(imu.rotation(100 * kMs, 300 * kMs));  // 200 ms without a sample
}

TEST(ImuBuffer, DropBeforeKeepsWhatTheNextIntervalNeeds) {
  ImuBuffer imu;
  const Eigen::Vector3d up(0, 0, 9.81), rate(0, 0, 1);
  for (int64_t t = 0; t <= 100 * kMs; t += 10 * kMs) ASSERT_TRUE(imu.add(t, up, rate));
  imu.drop_before(55 * kMs);
  EXPECT_EQ(imu.size(), 6u);  // 50 .. 100 ms
  const auto q = imu.rotation(55 * kMs, 100 * kMs);
  ASSERT_TRUE(q);
  EXPECT_NEAR(Eigen::AngleAxisd(*q).angle(), 0.045, 1e-9);
}

TEST(ImuBuffer, GravityAlignmentLevelsTheBodyAndKeepsTheLaunchYaw) {
  // a body pitched 0.1 rad nose up and rolled 0.05 rad, at rest
  const Eigen::Quaterniond truth = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX());
  const Eigen::Vector3d accel_body = truth.inverse() * Eigen::Vector3d(0, 0, 9.81);
  const Eigen::Quaterniond q = gravity_aligned_attitude(accel_body, 0.7);
  EXPECT_NEAR((q * accel_body - Eigen::Vector3d(0, 0, 9.81)).norm(), 0, 1e-9);
  const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(x.y(), x.x()), 0.7, 1e-9);
  EXPECT_NEAR(q.angularDistance(truth), 0, 1e-3);  // the same attitude, up to yaw conventions
  // level and at rest: the launch yaw only
  const Eigen::Quaterniond level = gravity_aligned_attitude(Eigen::Vector3d(0, 0, 9.81), -1.2);
  EXPECT_NEAR(
      level.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(-1.2, Eigen::Vector3d::UnitZ()))),
      0, 1e-12);
}

}  // namespace
}  // namespace scancrew::vio
