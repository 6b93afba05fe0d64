#include <gtest/gtest.h>

#include <cmath>

#include "sim/scene.hpp"

namespace scancrew::sim {
namespace {

std::string errors_of(const std::string& yaml) {
  auto scene = parse_scene(yaml, "s.yaml", "/nonexistent");
  if (scene) return "";
  std::string all;
  for (const auto& e : scene.error()) all += e + "\n";
  return all;
}

TEST(SceneLoader, ReadsBoxesCylindersAndBounds) {
  auto scene = parse_scene(R"(
name: room
bounds_min_m: [-4, -3.5, 0]
bounds_max_m: [4, 3.5, 2]
wall_height_m: 2
ceiling: true
boxes:
  - {name: pillar, center_m: [0, 0, 1], size_m: [0.8, 0.8, 2], yaw_deg: 30, color: [1, 0, 0]}
cylinders:
  - {name: drum, center_m: [2, 2, 0.5], radius_m: 0.3, height_m: 1}
)",
                           "room.yaml", ".");
  ASSERT_TRUE(scene) << scene.error().front();
  EXPECT_EQ(scene->name, "room");
  ASSERT_EQ(scene->boxes.size(), 1u);
  EXPECT_NEAR(scene->boxes[0].yaw_rad, M_PI / 6, 1e-12);
  EXPECT_DOUBLE_EQ(scene->boxes[0].size_m.x, 0.8);
  ASSERT_EQ(scene->cylinders.size(), 1u);
  EXPECT_TRUE(scene->ceiling);
}

TEST(SceneLoader, DegenerateGeometryIsNamed) {
  const std::string e = errors_of(R"(
name: bad
bounds_min_m: [0, 0, 0]
bounds_max_m: [1, 1, 0]
boxes:
  - {name: flat, center_m: [0, 0, 0], size_m: [1, 0, 1]}
cylinders:
  - {name: c, center_m: [0, 0, 0], radius_m: -1, height_m: 1}
)");
  EXPECT_NE(e.find("scene.bounds: degenerate"), std::string::npos) << e;
  EXPECT_NE(e.find("s.yaml:6: boxes[0].size_m: element '0' is invalid"), std::string::npos) << e;
  EXPECT_NE(e.find("cylinders[0].radius_m: -1 is out of range"), std::string::npos) << e;
}

TEST(SceneLoader, MissingMeshFileIsNamed) {
  const std::string e = errors_of(R"(
name: plant
bounds_min_m: [0, 0, 0]
bounds_max_m: [10, 10, 10]
meshes:
  - {name: plant, file: plant.obj, fit_m: [10, 10, 10], center_m: [5, 5, 0]}
)");
  EXPECT_NE(e.find("meshes[0].file: mesh file '/nonexistent/plant.obj' does not exist"),
            std::string::npos)
      << e;
}

TEST(SceneLoader, UnknownKeysAndMissingFieldsAreErrors) {
  const std::string e = errors_of(R"(
name: x
bounds_min_m: [0, 0, 0]
bounds_max_m: [1, 1, 1]
boxs: []
boxes:
  - {center_m: [0, 0, 0], size_m: [1, 1, 1], colour: [1, 1, 1]}
)");
  EXPECT_NE(e.find("scene.boxs: unknown parameter"), std::string::npos) << e;
  EXPECT_NE(e.find("boxes[0].name: missing required parameter"), std::string::npos) << e;
  EXPECT_NE(e.find("boxes[0].colour: unknown parameter"), std::string::npos) << e;
}

TEST(SceneLoader, TexturesAreDotsUnlessPlainIsAsked) {
  auto scene = parse_scene(R"(
name: plain
bounds_min_m: [-4, -3.5, 0]
bounds_max_m: [4, 3.5, 2]
wall_height_m: 2
walls_texture: plain
boxes:
  - {name: painted, center_m: [0, 0, 1], size_m: [0.8, 0.8, 2], texture: plain}
  - {name: dotted, center_m: [2, 0, 1], size_m: [0.8, 0.8, 2]}
cylinders:
  - {name: drum, center_m: [2, 2, 0.5], radius_m: 0.3, height_m: 1, texture: plain}
)",
                           "plain.yaml", ".");
  ASSERT_TRUE(scene) << scene.error().front();
  EXPECT_EQ(scene->walls_texture, SurfaceTexture::kPlain);
  ASSERT_EQ(scene->boxes.size(), 2u);
  EXPECT_EQ(scene->boxes[0].texture, SurfaceTexture::kPlain);
  EXPECT_EQ(scene->boxes[1].texture, SurfaceTexture::kDots);
  ASSERT_EQ(scene->cylinders.size(), 1u);
  EXPECT_EQ(scene->cylinders[0].texture, SurfaceTexture::kPlain);

  auto dotted =
      parse_scene("{name: d, bounds_min_m: [0, 0, 0], bounds_max_m: [1, 1, 1]}", "d.yaml", ".");
  ASSERT_TRUE(dotted) << dotted.error().front();
  EXPECT_EQ(dotted->walls_texture, SurfaceTexture::kDots);
}

TEST(SceneLoader, AnUnknownTextureNamesTheAllowedOnes) {
  const std::string e = errors_of(R"(
name: x
bounds_min_m: [0, 0, 0]
bounds_max_m: [1, 1, 1]
walls_texture: matte
boxes:
  - {name: b, center_m: [0.5, 0.5, 0.5], size_m: [0.1, 0.1, 0.1], texture: shiny}
)");
  EXPECT_NE(e.find("walls_texture"), std::string::npos) << e;
  EXPECT_NE(e.find("boxes[0].texture"), std::string::npos) << e;
  EXPECT_NE(e.find("plain"), std::string::npos) << e;
}

}  // namespace
}  // namespace scancrew::sim
