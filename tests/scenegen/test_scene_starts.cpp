// The scene file's starts: key (sim/scene_loader.cpp), which the generated scenes use:
// read per kind, checked, and listed by the shipped scenes.

#include <gtest/gtest.h>

#include <cmath>

#include "sim/scene.hpp"

namespace scancrew::sim {
namespace {

const char* kHead = "name: s\nbounds_min_m: [-2, -2, 0]\nbounds_max_m: [2, 2, 3]\n";

TEST(SceneStarts, AreReadPerKindWithTheirYaw) {
  auto s = parse_scene(std::string(kHead) +
                           "starts:\n  ground: [[-1, -1, 0, 90], [1, 1, 0, -45]]\n"
                           "  multirotor: [[0, 0, 2, 180]]\n",
                       "s.yaml", ".");
  ASSERT_TRUE(s) << s.error().front();
  ASSERT_EQ(s->starts.ground.size(), 2u);
  ASSERT_EQ(s->starts.multirotor.size(), 1u);
  EXPECT_DOUBLE_EQ(s->starts.ground[1].position_m.x, 1.0);
  EXPECT_NEAR(s->starts.ground[0].yaw_rad, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(s->starts.multirotor[0].position_m.z, 2.0);
}

TEST(SceneStarts, ASceneWithoutStartsHasNone) {
  auto s = parse_scene(kHead, "s.yaml", ".");
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->starts.ground.empty() && s->starts.multirotor.empty());
}

TEST(SceneStarts, BadStartsAreNamedWithTheFileLineAndKey) {
  auto s = parse_scene(std::string(kHead) +
                           "starts:\n"
                           "  ground: [[0, 0, 0], [5, 0, 0, 0], [0, 0, 0, 400]]\n"
                           "  aerial: []\n",
                       "s.yaml", ".");
  ASSERT_FALSE(s);
  const auto has = [&](const std::string& text) {
    for (const auto& e : s.error())
      if (e.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(has("starts.aerial: unknown parameter; known: ground, multirotor"));
  EXPECT_TRUE(has("s.yaml:5: scene.starts.ground[0]: allowed: [x, y, z, yaw_deg], four numbers"));
  EXPECT_TRUE(has("scene.starts.ground[1]: outside the bounds"));
  EXPECT_TRUE(has("scene.starts.ground[2]: yaw_deg 400 is out of range; allowed: [-360, 360]"));
  auto not_a_map = parse_scene(std::string(kHead) + "starts: [1, 2]\n", "s.yaml", ".");
  ASSERT_FALSE(not_a_map);
  EXPECT_NE(not_a_map.error().front().find("scene.starts: must be a mapping"), std::string::npos);
}

TEST(SceneStarts, TheShippedScenesListTheirMissionsStarts) {
  const std::string dir = std::string(SCANCREW_SOURCE_DIR) + "/launch_cfg/scenes/";
  auto arena = load_scene(dir + "test_arena.yaml");
  auto lot = load_scene(dir + "parking_lot.yaml");
  auto plant = load_scene(dir + "powerplant.yaml");
  ASSERT_TRUE(arena && lot && plant);
  EXPECT_EQ(arena->starts.ground.size(), 4u);
  ASSERT_EQ(lot->starts.ground.size(), 4u);
  EXPECT_DOUBLE_EQ(lot->starts.ground[0].position_m.x, -9.0);
  EXPECT_NEAR(lot->starts.ground[0].yaw_rad, M_PI / 6, 1e-12);
  ASSERT_EQ(plant->starts.multirotor.size(), 5u);
  EXPECT_DOUBLE_EQ(plant->starts.multirotor[0].position_m.z, 2.0);
  // the mixed team's two ground robots, on the floor
  ASSERT_EQ(plant->starts.ground.size(), 2u);
  EXPECT_DOUBLE_EQ(plant->starts.ground[0].position_m.z, 0.0);
}

}  // namespace
}  // namespace scancrew::sim
