#include <gtest/gtest.h>

#include "eval/free_space.hpp"

namespace scancrew::eval {
namespace {

using msg::Vec3;

sim::SceneSpec scene_of(const std::string& yaml) {
  auto scene = sim::parse_scene(yaml, "free.yaml", ".");
  EXPECT_TRUE(scene) << (scene ? "" : scene.error().front());
  return scene ? *scene : sim::SceneSpec{};
}

// Two 5 x 5 m rooms side by side (x < 0, x > 0) under 2 m walls, parted by a wall at x = 0
// with a door of door_m in its middle (0: closed).
sim::SceneSpec two_rooms(double door_m) {
  const double half = 0.5 * (5 - door_m), y = 2.5 - 0.5 * half;
  return scene_of(R"(
name: two_rooms
bounds_min_m: [-5, -2.5, 0]
bounds_max_m: [5, 2.5, 2]
wall_height_m: 2
boxes:
  - {name: lower, center_m: [0, )" +
                  std::to_string(-y) + R"(, 1], size_m: [0.2, )" + std::to_string(half) +
                  R"(, 2]}
  - {name: upper, center_m: [0, )" +
                  std::to_string(y) + R"(, 1], size_m: [0.2, )" + std::to_string(half) +
                  R"(, 2]}
)");
}

Result<FreeSpace, std::string> build(const sim::SceneSpec& scene, const FreeSpaceBody& body,
                                     const std::vector<Vec3>& starts) {
  const sim::SceneSolids solids(scene, {});
  return FreeSpace::build(solids, scene, body, starts);
}

TEST(FreeSpace, ARoomBehindAClosedDoorIsNotReachable) {
  auto fs = build(two_rooms(0), default_body(robot::RobotKind::kGround), {{-3, 0, 0}});
  ASSERT_TRUE(fs) << fs.error();
  EXPECT_TRUE(fs->start_free(0));
  EXPECT_FALSE(fs->connected());
  EXPECT_TRUE(fs->reachable({-3, 1, 0}));
  EXPECT_FALSE(fs->reachable({3, 0, 0}));
  // about half the free cells, each room's
  EXPECT_NEAR(static_cast<double>(fs->reachable_cells()) / static_cast<double>(fs->free_cells()),
              0.5, 0.02);
}

TEST(FreeSpace, AnOpenDoorConnectsTheRoomsAndANarrowOneDoesNot) {
  auto open = build(two_rooms(1.0), default_body(robot::RobotKind::kGround), {{-3, 0, 0}});
  ASSERT_TRUE(open) << open.error();
  EXPECT_TRUE(open->connected());
  EXPECT_TRUE(open->reachable({3, 0, 0}));
  // 0.4 m: narrower than the 0.5 m the body needs
  auto narrow = build(two_rooms(0.4), default_body(robot::RobotKind::kGround), {{-3, 0, 0}});
  ASSERT_TRUE(narrow) << narrow.error();
  EXPECT_FALSE(narrow->reachable({3, 0, 0}));
}

TEST(FreeSpace, AStartInsideABoxIsNotFree) {
  const sim::SceneSpec scene = scene_of(R"(
name: box
bounds_min_m: [-5, -5, 0]
bounds_max_m: [5, 5, 2]
boxes:
  - {name: box, center_m: [0, 0, 0.5], size_m: [2, 2, 1]}
)");
  auto fs = build(scene, default_body(robot::RobotKind::kGround), {{0, 0, 0}, {-3, -3, 0}});
  ASSERT_TRUE(fs) << fs.error();
  EXPECT_FALSE(fs->start_free(0));
  EXPECT_TRUE(fs->start_free(1));
  EXPECT_FALSE(fs->reachable({0, 0, 0}));
  EXPECT_TRUE(fs->connected());  // the second start reaches every free cell
  auto alone = build(scene, default_body(robot::RobotKind::kGround), {{0, 0, 0}});
  ASSERT_TRUE(alone) << alone.error();
  EXPECT_EQ(alone->reachable_cells(), 0u);
}

TEST(FreeSpace, AMultirotorFliesOverAWallThatStopsAGroundRobot) {
  sim::SceneSpec scene = two_rooms(0);
  scene.max_m.z = 6;
  FreeSpaceBody uav = default_body(robot::RobotKind::kMultirotor);
  uav.max_altitude_m = 5;
  // starts on the ground: moved up into the band
  auto fs = build(scene, uav, {{-3, 0, 0}});
  ASSERT_TRUE(fs) << fs.error();
  EXPECT_TRUE(fs->start_free(0));
  EXPECT_TRUE(fs->reachable({3, 0, 4}));
  EXPECT_TRUE(fs->reachable({3, 0, 1.5}));  // over the wall, then down
  EXPECT_FALSE(fs->reachable({3, 0, 7}));   // above the band
  // kept below the wall's top it cannot
  uav.max_altitude_m = 1.0;
  auto low = build(scene, uav, {{-3, 0, 1}});
  ASSERT_TRUE(low) << low.error();
  EXPECT_FALSE(low->reachable({3, 0, 1}));
}

TEST(FreeSpace, ReachablePositionsLieInReachableCellsOfEveryRegion) {
  auto fs = build(two_rooms(1.0), default_body(robot::RobotKind::kGround), {{-3, 0, 0}});
  ASSERT_TRUE(fs) << fs.error();
  const auto positions = fs->reachable_positions(1.0);
  for (const Vec3& p : positions) EXPECT_TRUE(fs->reachable(p));
  // about one a square metre of the reachable area
  const double area = static_cast<double>(fs->reachable_cells()) * 0.2 * 0.2;
  EXPECT_NEAR(static_cast<double>(positions.size()), area, 0.25 * area);
  // both rooms get positions
  size_t right = 0;
  for (const Vec3& p : positions) right += p.x > 0.5 ? 1 : 0;
  EXPECT_NEAR(static_cast<double>(right), 0.5 * static_cast<double>(positions.size()),
              0.1 * static_cast<double>(positions.size()));
}

TEST(FreeSpace, RefusesBadBodiesAndNoStarts) {
  const sim::SceneSpec scene = two_rooms(0);
  FreeSpaceBody body = default_body(robot::RobotKind::kGround);
  body.radius_m = 0;
  EXPECT_FALSE(build(scene, body, {{-3, 0, 0}}));
  FreeSpaceBody uav = default_body(robot::RobotKind::kMultirotor);
  uav.min_altitude_m = 5;
  uav.max_altitude_m = 2;
  auto e = build(scene, uav, {{-3, 0, 3}});
  ASSERT_FALSE(e);
  EXPECT_NE(e.error().find("altitude band"), std::string::npos) << e.error();
  EXPECT_FALSE(build(scene, default_body(robot::RobotKind::kGround), {}));
}

}  // namespace
}  // namespace scancrew::eval
