// The robot kinds and the body model: names both ways, the thesis's sizes (tables 2.1 and
// 5.3), and the safety ellipsoid's derived sizes.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "core/robot/body_model.hpp"
#include "core/robot/robot_kind.hpp"

namespace scancrew::robot {
namespace {

TEST(RobotKind, NamesParseBackAndAnUnknownNameListsTheKinds) {
  for (const RobotKind k : {RobotKind::kGround, RobotKind::kMultirotor}) {
    const auto parsed = parse_robot_kind(to_string(k));
    ASSERT_TRUE(parsed);
    EXPECT_EQ(*parsed, k);
  }
  const auto boat = parse_robot_kind("boat");
  ASSERT_FALSE(boat);
  EXPECT_EQ(boat.error(), "unknown robot kind 'boat' (ground | multirotor)");
  EXPECT_EQ(kind_bit(RobotKind::kGround) | kind_bit(RobotKind::kMultirotor), 3U);
}

TEST(BodyModel, EachKindHasTheThesisSafetyVolume) {
  const BodyModel ground = BodyModel::of(RobotKind::kGround);
  EXPECT_EQ(ground.kind, RobotKind::kGround);
  EXPECT_DOUBLE_EQ(ground.safety_radii_m.x(), 0.55);  // table 5.3, along the heading
  EXPECT_DOUBLE_EQ(ground.safety_radii_m.y(), 0.25);  // table 5.3, across
  EXPECT_DOUBLE_EQ(ground.bounding_radius_m(), 0.55);
  EXPECT_DOUBLE_EQ(ground.footprint_radius_m(), 0.25);
  const BodyModel multirotor = BodyModel::of(RobotKind::kMultirotor);
  EXPECT_EQ(multirotor.kind, RobotKind::kMultirotor);
  EXPECT_DOUBLE_EQ(multirotor.bounding_radius_m(), 1.0);  // table 2.1's collision radius
  EXPECT_DOUBLE_EQ(multirotor.footprint_radius_m(), 1.0);
  // the frames fit inside their safety volumes
  for (const BodyModel& b : {ground, multirotor})
    EXPECT_TRUE((b.frame_half_m.array() < b.safety_radii_m.array()).all()) << to_string(b.kind);
}

TEST(BodyModel, TheBoxAroundTheTurnedEllipsoidIsExact) {
  const BodyModel ground = BodyModel::of(RobotKind::kGround).inflated(0.05);
  EXPECT_DOUBLE_EQ(ground.safety_radii_m.x(), 0.60);
  const Eigen::Vector3d level = ground.aabb_half_extents(Eigen::Matrix3d::Identity());
  EXPECT_TRUE(level.isApprox(ground.safety_radii_m));
  // turned 90° about z: the long axis lies along y
  const Eigen::Matrix3d quarter =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d turned = ground.aabb_half_extents(quarter);
  EXPECT_NEAR(turned.x(), 0.30, 1e-12);
  EXPECT_NEAR(turned.y(), 0.60, 1e-12);
  // 45°: sqrt((a² + b²) / 2) on x and y
  const Eigen::Matrix3d eighth =
      Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(ground.aabb_half_extents(eighth).x(), std::sqrt((0.36 + 0.09) / 2), 1e-12);
}

}  // namespace
}  // namespace scancrew::robot
