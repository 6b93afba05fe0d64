#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sim/scene_solids.hpp"

namespace scancrew::sim {
namespace {

using msg::Vec3;

SceneSpec scene_of(const std::string& yaml) {
  auto scene = parse_scene(yaml, "solids.yaml", ".");
  EXPECT_TRUE(scene) << (scene ? "" : scene.error().front());
  return scene ? *scene : SceneSpec{};
}

// A 10 x 10 x 3 m room with walls and a ceiling, a box (1 x 1 x 1 at (2, 0)), a box turned by
// 45 degrees at (-2, 0), a cylinder (r 0.5, 2 m tall) at (0, 2).
SceneSpec room() {
  return scene_of(R"(
name: room
bounds_min_m: [-5, -5, 0]
bounds_max_m: [5, 5, 3]
wall_height_m: 3
ceiling: true
boxes:
  - {name: box, center_m: [2, 0, 0.5], size_m: [1, 1, 1]}
  - {name: turned, center_m: [-2, 0, 0.5], size_m: [2, 0.2, 1], yaw_deg: 45}
cylinders:
  - {name: drum, center_m: [0, 2, 1], radius_m: 0.5, height_m: 2}
)");
}

// One triangle standing in the plane x = 0, over y in [-1, 1], z in [0, 2].
TriangleMesh standing_triangle() {
  return {.vertices = {{0, -1, 0}, {0, 1, 0}, {0, 0, 2}}, .triangles = {{0, 1, 2}}};
}

TEST(SceneSolids, ListsTheFloorCeilingWallsBoxesAndCylindersInOrder) {
  const SceneSolids solids(room(), {});
  ASSERT_EQ(solids.solids().size(), 1u + 1u + 4u + 2u + 1u);
  EXPECT_EQ(solids.solids()[0].kind, Solid::Kind::kBelowFloor);
  EXPECT_EQ(solids.ceiling_index(), 1);
  EXPECT_EQ(solids.wall_index(0), 2);
  EXPECT_EQ(solids.box_index(1), 7);
  EXPECT_EQ(solids.cylinder_index(0), 8);
  EXPECT_EQ(solids.solids()[8].kind, Solid::Kind::kCylinder);
}

TEST(SceneSolids, ASegmentThroughABoxIsBlockedAndOneBesideItIsNot) {
  const SceneSolids solids(room(), {});
  EXPECT_TRUE(solids.segment_blocked({1, 0, 0.5}, {3, 0, 0.5}, 0.01));
  EXPECT_FALSE(solids.segment_blocked({1, 0.6, 0.5}, {3, 0.6, 0.5}, 0.01));
  EXPECT_FALSE(solids.segment_blocked({1, 0, 1.1}, {3, 0, 1.1}, 0.01));  // over it
}

TEST(SceneSolids, AYawedBoxBlocksAlongItsTurnedExtent) {
  const SceneSolids solids(room(), {});
  // the 2 x 0.2 m box along the diagonal: its end reaches (-2 + 0.7, 0.7)
  EXPECT_TRUE(solids.segment_blocked({-1.3, 0, 0.5}, {-1.3, 1, 0.5}, 0.01));
  // where an unturned box would stand, at (-1.3, -0.05), the turned one is not
  EXPECT_FALSE(solids.segment_blocked({-1.3, -0.3, 0.5}, {-1.3, -0.1, 0.5}, 0.01));
}

TEST(SceneSolids, ASegmentThroughACylinderIsBlockedAndOnePastItsSideIsNot) {
  const SceneSolids solids(room(), {});
  EXPECT_TRUE(solids.segment_blocked({-1, 2, 1}, {1, 2, 1}, 0.01));
  EXPECT_TRUE(solids.segment_blocked({0, 2, 2.5}, {0, 2, 1.5}, 0.01));  // down through its top
  EXPECT_FALSE(solids.segment_blocked({-1, 2.6, 1}, {1, 2.6, 1}, 0.01));
  EXPECT_FALSE(solids.segment_blocked({-1, 2, 2.2}, {1, 2, 2.2}, 0.01));
}

TEST(SceneSolids, WallsCeilingAndFloorBlock) {
  const SceneSolids solids(room(), {});
  EXPECT_TRUE(solids.segment_blocked({4, -3, 1}, {6, -3, 1}, 0.01));     // the +x wall
  EXPECT_TRUE(solids.segment_blocked({-4, -3, 2}, {-4, -3, 4}, 0.01));   // the ceiling
  EXPECT_TRUE(solids.segment_blocked({-4, -3, 1}, {-4, -3, -1}, 0.01));  // the floor
  EXPECT_FALSE(solids.segment_blocked({-4, -3, 0.1}, {4, -3, 2.9}, 0.01));
}

TEST(SceneSolids, TheEndMarginLetsASegmentEndOnASurface) {
  const SceneSolids solids(room(), {});
  // ends on the box's -x face, on the floor, on the ceiling
  EXPECT_FALSE(solids.segment_blocked({0, 0, 0.5}, {1.5, 0, 0.5}, 0.01));
  EXPECT_FALSE(solids.segment_blocked({0, -3, 1}, {1, -3, 0}, 0.01));
  EXPECT_FALSE(solids.segment_blocked({0, -3, 1}, {1, -3, 3}, 0.01));
  // without a margin the end point itself lies on the surface: still not inside
  EXPECT_FALSE(solids.segment_blocked({0, 0, 0.5}, {1.5, 0, 0.5}, 0));
  // through the box and out of its far side, ending on its +x face from inside
  EXPECT_TRUE(solids.segment_blocked({0, 0, 0.5}, {2.5, 0, 0.5}, 0.01));
}

TEST(SceneSolids, MeshTrianglesBlockSegmentsAndBodies) {
  const SceneSpec scene = scene_of(R"(
name: open
bounds_min_m: [-5, -5, 0]
bounds_max_m: [5, 5, 3]
)");
  const SceneSolids solids(scene, {standing_triangle()});
  EXPECT_EQ(solids.triangle_count(), 1u);
  EXPECT_TRUE(solids.segment_blocked({-1, 0, 0.5}, {1, 0, 0.5}, 0.01));
  EXPECT_FALSE(solids.segment_blocked({-1, 0.5, 1.8}, {1, 0.5, 1.8}, 0.01));  // beside its apex
  EXPECT_TRUE(solids.cylinder_overlaps(0.2, 0, 0.3, 0.05, 0.4));
  EXPECT_FALSE(solids.cylinder_overlaps(0.4, 0, 0.3, 0.05, 0.4));
  EXPECT_FALSE(solids.cylinder_overlaps(0, 0, 0.3, 2.1, 2.5));    // above it
  EXPECT_TRUE(solids.cylinder_overlaps(0, 0.5, 0.1, 0.05, 0.4));  // inside its outline
  EXPECT_TRUE(solids.sphere_overlaps({0.9, 0, 1}, 1.0));
  EXPECT_FALSE(solids.sphere_overlaps({1.1, 0, 1}, 1.0));
  EXPECT_FALSE(solids.sphere_overlaps({0, 0, 3.1}, 1.0));  // above the apex
}

TEST(SceneSolids, BodiesOverlapBoxesCylindersWallsAndTheFloor) {
  const SceneSolids solids(room(), {});
  EXPECT_FALSE(solids.cylinder_overlaps(0, -2, 0.3, 0.05, 0.4));
  EXPECT_TRUE(solids.cylinder_overlaps(1.3, 0, 0.3, 0.05, 0.4));   // beside the box, 0.2 m
  EXPECT_FALSE(solids.cylinder_overlaps(1.1, 0, 0.3, 1.05, 1.4));  // over it
  EXPECT_TRUE(solids.cylinder_overlaps(0, 1.3, 0.3, 0.05, 0.4));   // the cylinder
  EXPECT_TRUE(solids.cylinder_overlaps(4.8, -3, 0.3, 0.05, 0.4));  // the +x wall
  EXPECT_TRUE(solids.cylinder_overlaps(0, -2, 0.3, -0.1, 0.4));    // below the floor
  EXPECT_FALSE(solids.sphere_overlaps({0, -2, 1.5}, 1.0));
  EXPECT_TRUE(solids.sphere_overlaps({0, -2, 0.9}, 1.0));      // the floor
  EXPECT_TRUE(solids.sphere_overlaps({0, -2, 2.1}, 1.0));      // the ceiling
  EXPECT_TRUE(solids.sphere_overlaps({2, 0, 1.9}, 1.0));       // the box's top
  EXPECT_FALSE(solids.sphere_overlaps({3.3, 1.3, 1.5}, 1.0));  // past its corner: 1.24 m away
  EXPECT_TRUE(solids.sphere_overlaps({0, 3.2, 2.5}, 1.0));     // the cylinder's top rim, 0.87 m
}

// The grid of boxes and cylinders answers as testing every solid would.
TEST(SceneSolids, TheGridAgreesWithTestingEverySolid) {
  std::string yaml =
      "name: yard\nbounds_min_m: [-50, -50, 0]\nbounds_max_m: [50, 50, 10]\nboxes:\n";
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> xy(-48, 48), size(0.2, 3), yaw(0, 90);
  for (int i = 0; i < 300; ++i)
    yaml += "  - {name: b" + std::to_string(i) + ", center_m: [" + std::to_string(xy(rng)) + ", " +
            std::to_string(xy(rng)) + ", 1], size_m: [" + std::to_string(size(rng)) + ", " +
            std::to_string(size(rng)) + ", 2], yaw_deg: " + std::to_string(yaw(rng)) + "}\n";
  yaml += "cylinders:\n";
  for (int i = 0; i < 200; ++i)
    yaml += "  - {name: c" + std::to_string(i) + ", center_m: [" + std::to_string(xy(rng)) + ", " +
            std::to_string(xy(rng)) + ", 2], radius_m: 0.4, height_m: 4}\n";
  const SceneSolids solids(scene_of(yaml), {});
  std::uniform_real_distribution<double> z(0.1, 5), step(-8, 8);
  int blocked = 0, overlapping = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 a{xy(rng), xy(rng), z(rng)}, b{a.x + step(rng), a.y + step(rng), z(rng)};
    const double length = std::hypot(b.x - a.x, b.y - a.y, b.z - a.z);
    if (!(length > 0.02)) continue;
    bool exact = false, body = false;
    for (const Solid& s : solids.solids()) {
      exact = exact || s.crossed_by(a, b, 0.01 / length, 1 - 0.01 / length);
      body = body || s.overlaps_sphere(a, 1.0);
    }
    EXPECT_EQ(solids.segment_blocked(a, b, 0.01), exact) << i;
    EXPECT_EQ(solids.sphere_overlaps(a, 1.0), body) << i;
    blocked += exact ? 1 : 0;
    overlapping += body ? 1 : 0;
  }
  EXPECT_GT(blocked, 100);  // the comparison saw both answers
  EXPECT_GT(overlapping, 100);
}

}  // namespace
}  // namespace scancrew::sim
