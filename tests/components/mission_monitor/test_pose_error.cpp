// PoseError (components/mission_monitor/pose_error.hpp): an odometry's error against the truth
// per robot, and two robots' frames against each other, on hand-made trajectories whose
// errors are known in closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "components/mission_monitor/pose_error.hpp"

namespace scancrew::mission_monitor {
namespace {

constexpr int64_t kFrameNs = 100'000'000;  // 10 Hz

msg::Odometry pose_at(int64_t stamp_ns, double x, double y, double yaw_rad = 0) {
  msg::Odometry o;
  o.header.stamp_ns = stamp_ns;
  o.T_world_body.position = {x, y, 0};
  o.T_world_body.orientation = {std::cos(yaw_rad / 2), 0, 0, std::sin(yaw_rad / 2)};
  return o;
}

// Robot 0 drives along +x from (0, 0), robot 1 along +x from (0, 2), 0.1 m per frame, for
// `frames` frames; estimate(robot, truth) gives each estimate from its truth.
template <typename Estimate>
void drive(PoseError& e, int frames, Estimate estimate) {
  for (int k = 0; k < frames; ++k) {
    const int64_t t = k * kFrameNs;
    for (size_t r = 0; r < 2; ++r) {
      const msg::Odometry truth = pose_at(t, 0.1 * k, 2.0 * static_cast<double>(r));
      e.on_truth(r, truth);
      e.on_estimate(r, estimate(r, truth));
    }
    e.sample(t);
  }
}

TEST(PoseError, AnOffsetOdometryHasThatAteAndThatDisagreementWithAnExactTeammate) {
  PoseError e(2);
  drive(e, 51, [](size_t r, msg::Odometry o) {
    if (r == 1) o.T_world_body.position.x += 0.2;  // robot 1's frame is 0.2 m off along x
    return o;
  });
  const auto exact = e.robot_error(0);
  const auto off = e.robot_error(1);
  ASSERT_TRUE(exact && off);
  EXPECT_EQ(exact->matched, 51u);
  EXPECT_NEAR(exact->ate_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(off->ate_rmse_m, 0.2, 1e-9);
  EXPECT_NEAR(off->distance_m, 5.0, 1e-9);  // 50 steps of 0.1 m
  const std::vector<PoseError::Pair> pairs = e.pairs();
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].samples, 51u);
  EXPECT_NEAR(pairs[0].mean_m, 0.2, 1e-9);
  EXPECT_NEAR(pairs[0].max_m, 0.2, 1e-9);
  EXPECT_NEAR(pairs[0].max_yaw_deg, 0.0, 1e-9);
}

TEST(PoseError, AFrameTurnedAboutTheOriginDisagreesByTheChordAtTheRobotsMidpoint) {
  const double yaw = 5.0 * M_PI / 180.0;
  PoseError e(2);
  drive(e, 11, [yaw](size_t r, msg::Odometry o) {
    if (r == 0) return o;
    // robot 1's estimate: its true pose seen in a frame turned by `yaw` about the origin
    const double x = o.T_world_body.position.x, y = o.T_world_body.position.y;
    return pose_at(o.header.stamp_ns, std::cos(yaw) * x - std::sin(yaw) * y,
                   std::sin(yaw) * x + std::cos(yaw) * y, yaw);
  });
  // last sample: robots at (1, 0) and (1, 2), midpoint (1, 1) at sqrt(2) from the origin;
  // the turned frame moves it by the chord 2·sqrt(2)·sin(yaw / 2)
  const PoseError::Pair pair = e.pairs().at(0);
  EXPECT_NEAR(pair.last_m, 2.0 * std::sqrt(2.0) * std::sin(yaw / 2), 1e-9);
  EXPECT_NEAR(pair.max_yaw_deg, 5.0, 1e-9);
}

TEST(PoseError, AnEstimateWithoutTheTruthOfItsFrameIsNotScored) {
  PoseError e(2);
  EXPECT_FALSE(e.robot_error(0).has_value());
  e.on_truth(0, pose_at(0, 0, 0));
  e.on_estimate(0, pose_at(kFrameNs / 2, 0, 0));  // no truth of this stamp
  EXPECT_EQ(e.matched(0), 0u);
  e.on_estimate(0, pose_at(0, 0.1, 0));
  EXPECT_EQ(e.matched(0), 1u);
  // robot 1 has no estimate: nothing to compare, no pairwise sample
  e.sample(0);
  EXPECT_EQ(e.pairs().at(0).samples, 0u);
}

TEST(PoseError, AStaleEstimateIsLeftOutOfThePairwiseSample) {
  PoseError e(2);
  for (size_t r = 0; r < 2; ++r) {
    e.on_truth(r, pose_at(0, 0, 2.0 * static_cast<double>(r)));
    e.on_estimate(r, pose_at(0, 0.3, 2.0 * static_cast<double>(r)));
  }
  e.sample(500'000'000);    // both half a second old: sampled
  e.sample(1'500'000'000);  // 1.5 s old: a robot whose odometry stopped answering is not
  EXPECT_EQ(e.pairs().at(0).samples, 1u);
}

}  // namespace
}  // namespace scancrew::mission_monitor
