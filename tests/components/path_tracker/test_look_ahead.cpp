// The look-ahead pose on a local path: distance_m ahead of the robot's projection, the
// progress never going back nor jumping to a nearby later leg, the final waypoint (and
// its yaw) at the end, and bad paths refused.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "components/path_tracker/look_ahead.hpp"

namespace scancrew::path_tracker {
namespace {

msg::Waypoint wp(double x, double y, double z, double yaw = 0) {
  return {{x, y, z}, yaw};
}

TEST(LookAhead, TargetsTheDistanceAheadOfTheProjection) {
  LookAhead la({.distance_m = 0.5});
  ASSERT_TRUE(la.set_path({wp(0, 0, 1), wp(2, 0, 1), wp(2, 2, 1, 1.0), wp(4, 2, 1, 0.3)}));
  EXPECT_NEAR(la.length_m(), 6.0, 1e-12);
  const LookAheadTarget t = la.update({1.0, 0.2, 1.0});
  EXPECT_NEAR((t.position_m - Eigen::Vector3d(1.5, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t.yaw_rad, 0.0, 1e-12);  // tangent of the first leg
  EXPECT_NEAR(t.cross_track_m, 0.2, 1e-12);
  EXPECT_NEAR(t.progress_m, 1.0, 1e-12);
  EXPECT_NEAR(t.remaining_m, 5.0, 1e-12);
  EXPECT_EQ(t.next_index, 1u);
  EXPECT_FALSE(t.at_end);
  // around the corner: the target is on the second leg, heading +y
  const LookAheadTarget c = la.update({1.8, 0.0, 1.0});
  EXPECT_NEAR((c.position_m - Eigen::Vector3d(2, 0.3, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(c.yaw_rad, M_PI / 2, 1e-12);
}

TEST(LookAhead, EndsOnTheFinalWaypointWithItsYaw) {
  LookAhead la({.distance_m = 0.5});
  ASSERT_TRUE(la.set_path({wp(0, 0, 1), wp(2, 0, 1), wp(2, 2, 1, 1.0), wp(4, 2, 1, 0.3)}));
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1.5, 0, 1), Eigen::Vector3d(2.1, 1.5, 1)})
    EXPECT_FALSE(la.update(p).at_end);
  const LookAheadTarget t = la.update({3.7, 2.1, 1.0});
  EXPECT_TRUE(t.at_end);
  EXPECT_NEAR((t.position_m - Eigen::Vector3d(4, 2, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t.yaw_rad, 0.3, 1e-12);
  EXPECT_EQ(t.next_index, 3u);
}

TEST(LookAhead, ProgressNeverGoesBack) {
  LookAhead la({.distance_m = 0.5});
  ASSERT_TRUE(la.set_path({wp(0, 0, 0), wp(4, 0, 0)}));
  EXPECT_NEAR(la.update({2.0, 0.0, 0.0}).progress_m, 2.0, 1e-12);
  const LookAheadTarget back = la.update({1.0, 0.5, 0.0});  // pushed back
  EXPECT_NEAR(back.progress_m, 2.0, 1e-12);
  EXPECT_NEAR(back.position_m.x(), 2.5, 1e-12);
}

TEST(LookAhead, DoesNotJumpToALaterLegThatPassesNearby) {
  // a U: out along y = 0, back along y = 0.6; the robot is on the first leg, near the second
  LookAhead la({.distance_m = 0.5, .search_window_m = 2.0});
  ASSERT_TRUE(la.set_path({wp(0, 0, 0), wp(4, 0, 0), wp(4, 0.6, 0), wp(0, 0.6, 0)}));
  const LookAheadTarget t = la.update({1.0, 0.35, 0.0});
  EXPECT_NEAR(t.progress_m, 1.0, 1e-12);
  EXPECT_EQ(t.next_index, 1u);
  EXPECT_NEAR(t.position_m.y(), 0.0, 1e-12);
}

TEST(LookAhead, PlanarPathsIgnoreHeightInTheProjection) {
  LookAhead la({.distance_m = 1.0, .planar = true});
  ASSERT_TRUE(la.set_path({wp(0, 0, 0), wp(3, 0, 0.3)}));
  EXPECT_NEAR(la.length_m(), 3.0, 1e-12);
  const LookAheadTarget t = la.update({1.0, 0.0, 5.0});
  EXPECT_NEAR(t.cross_track_m, 0.0, 1e-12);
  EXPECT_NEAR(t.position_m.x(), 2.0, 1e-12);
  EXPECT_NEAR(t.position_m.z(), 0.2, 1e-12);  // the waypoints' own height, interpolated
}

TEST(LookAhead, TakesTheWaypointYawsOnRequestAndTangentsAcrossClimbs) {
  const std::vector<msg::Waypoint> path = {wp(0, 0, 1, 0.0), wp(0, 0, 2, 0.5), wp(2, 0, 2, 1.2),
                                           wp(2, 2, 2, 2.0)};
  LookAhead tangent({.distance_m = 0.5});
  ASSERT_TRUE(tangent.set_path(path));
  // on the climb: the tangent of the next leg with a horizontal extent (+x)
  EXPECT_NEAR(tangent.update({0, 0, 1.2}).yaw_rad, 0.0, 1e-12);
  LookAhead own({.distance_m = 0.5, .yaw_source = YawSource::kWaypoints});
  ASSERT_TRUE(own.set_path(path));
  EXPECT_NEAR(own.update({0, 0, 1.2}).yaw_rad, 0.5, 1e-12);  // the climb's end waypoint
  EXPECT_NEAR(own.update({1.0, 0, 2}).yaw_rad, 1.2, 1e-12);  // the x leg's end waypoint
}

TEST(LookAhead, ASingleWaypointIsTheGoal) {
  LookAhead la;
  ASSERT_TRUE(la.set_path({wp(1, 2, 0, 0.7)}));
  const LookAheadTarget t = la.update({0, 0, 0});
  EXPECT_TRUE(t.at_end);
  EXPECT_NEAR((t.position_m - Eigen::Vector3d(1, 2, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t.yaw_rad, 0.7, 1e-12);
  EXPECT_NEAR(t.cross_track_m, std::sqrt(5.0), 1e-12);
}

TEST(LookAhead, RepeatedWaypointsDoNotBreakTheProjection) {
  LookAhead la({.distance_m = 0.5});
  ASSERT_TRUE(la.set_path({wp(0, 0, 0), wp(0, 0, 0), wp(2, 0, 0), wp(2, 0, 0), wp(2, 2, 0)}));
  const LookAheadTarget t = la.update({1.9, 0.0, 0.0});
  EXPECT_NEAR((t.position_m - Eigen::Vector3d(2, 0.4, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t.yaw_rad, M_PI / 2, 1e-12);
  EXPECT_TRUE(std::isfinite(t.cross_track_m));
}

TEST(LookAhead, RefusesEmptyAndNonFinitePaths) {
  LookAhead la;
  ASSERT_TRUE(la.set_path({wp(0, 0, 0), wp(1, 0, 0)}));
  auto empty = la.set_path({});
  ASSERT_FALSE(empty);
  EXPECT_EQ(empty.error(), "empty path");
  EXPECT_FALSE(la.has_path());
  auto nan = la.set_path({wp(0, 0, 0), wp(std::numeric_limits<double>::quiet_NaN(), 0, 0)});
  ASSERT_FALSE(nan);
  EXPECT_EQ(nan.error(), "waypoint 1 is not finite");
  EXPECT_FALSE(la.has_path());
}

}  // namespace
}  // namespace scancrew::path_tracker
