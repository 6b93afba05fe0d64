// Ground-truth surface points: counts match the analytic visible area, nothing hidden is
// kept (faces on the floor, under the ceiling, shared by touching solids), normals are unit
// and outward, the output is reproducible, and the PLY file is what the header says.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "sim/surface_sampler.hpp"
#include "tests/sim/test_meshes.hpp"

namespace scancrew::sim {
namespace {

constexpr double kDensity = 2000;

// a 6 x 4 x 2.5 m room: four 0.1 m walls 2.5 m high, a ceiling
SceneSpec room(bool walls = true, bool ceiling = true) {
  SceneSpec s;
  s.name = "room";
  s.min_m = {-3, -2, 0};
  s.max_m = {3, 2, 2.5};
  s.ceiling = ceiling;
  s.wall_height_m = walls ? 2.5 : 0;
  s.wall_thickness_m = 0.1;
  return s;
}

// 0.8 x 0.6 x 1.0 m, on the floor, turned by 0.3 rad
BoxSpec turned_box() {
  return {.name = "box", .center_m = {1, 0.5, 0.5}, .size_m = {0.8, 0.6, 1.0}, .yaw_rad = 0.3};
}

SurfaceSamples sample(const SceneSpec& scene, const std::vector<TriangleMesh>& meshes = {},
                      uint64_t seed = 1, double density = kDensity) {
  auto r = sample_surfaces(scene, meshes, {.density_per_m2 = density, .seed = seed});
  EXPECT_TRUE(r) << (r ? "" : r.error());
  return r ? std::move(r).value() : SurfaceSamples{};
}

// p in the frame of a box turned by yaw about its centre
msg::Vec3 box_local(const std::array<float, 3>& p, const BoxSpec& b) {
  const double dx = p[0] - b.center_m.x, dy = p[1] - b.center_m.y;
  const double c = std::cos(b.yaw_rad), s = std::sin(b.yaw_rad);
  return {dx * c + dy * s, -dx * s + dy * c, p[2] - b.center_m.z};
}

TEST(SurfaceSampler, CountMatchesAnalyticVisibleArea) {
  SceneSpec scene = room();
  scene.boxes.push_back(turned_box());
  const auto s = sample(scene);
  // floor less the box's footprint, ceiling, inner walls, the box's top and four sides
  const double floor = 6 * 4 - 0.8 * 0.6, ceiling = 6 * 4, walls = 2 * (6 + 4) * 2.5;
  const double box = 0.8 * 0.6 + 2 * (0.8 * 1.0) + 2 * (0.6 * 1.0);
  const double area = floor + ceiling + walls + box;  // 100.8 m2
  const double expected = area * kDensity;
  EXPECT_NEAR(static_cast<double>(s.points.size()), expected, 3 * std::sqrt(expected));
  EXPECT_NEAR(s.area_m2, area, 3 * std::sqrt(expected) / kDensity);
  EXPECT_EQ(s.points.size(), s.normals.size());
}

TEST(SurfaceSampler, KeepsNothingHiddenAndNormalsAreUnitAndOutward) {
  SceneSpec scene = room();
  const BoxSpec b = turned_box();
  scene.boxes.push_back(b);
  const auto s = sample(scene);
  const double hx = 0.4, hy = 0.3, hz = 0.5, tol = 1e-5;
  size_t on_top = 0, on_sides = 0;
  for (size_t i = 0; i < s.points.size(); ++i) {
    const auto& p = s.points[i];
    const auto& n = s.normals[i];
    ASSERT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-6);
    ASSERT_GE(p[2], 0.0f) << "below the floor";
    ASSERT_TRUE(p[0] >= -3 - kHiddenTolerance && p[0] <= 3 + kHiddenTolerance &&
                p[1] >= -2 - kHiddenTolerance && p[1] <= 2 + kHiddenTolerance &&
                p[2] <= 2.5 + kHiddenTolerance)
        << "outside the bounds: " << p[0] << " " << p[1] << " " << p[2];
    const msg::Vec3 l = box_local(p, b);
    const bool in_x = std::abs(l.x) < hx - tol, in_y = std::abs(l.y) < hy - tol,
               in_z = std::abs(l.z) < hz - tol;
    ASSERT_FALSE(in_x && in_y && in_z) << "inside the box";
    ASSERT_FALSE(in_x && in_y && p[2] < tol) << "on the box's bottom or the floor under it";
    if (in_x && in_y && std::abs(l.z - hz) < tol) {
      ++on_top;
      ASSERT_EQ(n[2], 1.0f) << "box top facing +z";
    }
    const bool on_box = std::abs(l.x) < hx + tol && std::abs(l.y) < hy + tol && p[2] < 2 * hz;
    if (on_box && p[2] < 2 * hz - tol) {
      ++on_sides;
      // outward: the normal points away from the box's axis
      const double rx = p[0] - b.center_m.x, ry = p[1] - b.center_m.y;
      ASSERT_GT(n[0] * rx + n[1] * ry, 0.0) << "side normal points into the box";
    }
  }
  EXPECT_NEAR(static_cast<double>(on_top), 0.48 * kDensity, 3 * std::sqrt(0.48 * kDensity));
  EXPECT_NEAR(static_cast<double>(on_sides), 2.8 * kDensity, 3 * std::sqrt(2.8 * kDensity));
}

TEST(SurfaceSampler, TouchingBoxesHideTheSharedFace) {
  SceneSpec scene = room(false, false);
  scene.boxes.push_back({.name = "a", .center_m = {0, 0, 0.5}, .size_m = {1, 1, 1}});
  scene.boxes.push_back({.name = "b", .center_m = {1, 0, 0.5}, .size_m = {1, 1, 1}});
  const auto s = sample(scene);
  size_t tops = 0;
  for (const auto& p : s.points) {
    const bool on_shared =
        std::abs(p[0] - 0.5) < 1e-4 && std::abs(p[1]) < 0.499 && p[2] > 0.001 && p[2] < 0.999;
    ASSERT_FALSE(on_shared) << "point on the shared face at " << p[1] << " " << p[2];
    if (std::abs(p[2] - 1) < 1e-6) ++tops;
  }
  EXPECT_NEAR(static_cast<double>(tops), 2 * kDensity, 3 * std::sqrt(2 * kDensity));
  // floor 24 - 2, the two tops 2, the outer sides 6 (4 faces of 1 m2 are hidden: 2 bottoms,
  // 2 shared)
  const double area = 22 + 2 + 6;
  EXPECT_NEAR(s.area_m2, area, 3 * std::sqrt(area * kDensity) / kDensity);
}

TEST(SurfaceSampler, PillarUnderTheCeilingHasNoTop) {
  SceneSpec scene = room();
  scene.cylinders.push_back(
      {.name = "pillar", .center_m = {0, 0, 1.25}, .radius_m = 0.3, .height_m = 2.5});
  const auto s = sample(scene);
  size_t side = 0;
  for (size_t i = 0; i < s.points.size(); ++i) {
    const auto& p = s.points[i];
    const double r = std::hypot(p[0], p[1]);
    ASSERT_FALSE(r < 0.299 && (std::abs(p[2] - 2.5) < 1e-4 || p[2] < 1e-4))
        << "on the pillar's top or bottom, or on the ceiling or floor it covers";
    if (std::abs(r - 0.3) < 1e-5) {
      ++side;
      ASSERT_NEAR(s.normals[i][0], p[0] / r, 1e-4);
      ASSERT_NEAR(s.normals[i][1], p[1] / r, 1e-4);
    }
  }
  const double side_area = 2 * std::numbers::pi * 0.3 * 2.5;
  EXPECT_NEAR(static_cast<double>(side), side_area * kDensity, 3 * std::sqrt(side_area * kDensity));
  const double area = 2 * (24 - std::numbers::pi * 0.09) + 50 + side_area;
  EXPECT_NEAR(s.area_m2, area, 3 * std::sqrt(area * kDensity) / kDensity);
}

TEST(SurfaceSampler, SameSeedSameOutputOtherSeedOtherOutput) {
  SceneSpec scene = room();
  scene.boxes.push_back(turned_box());
  const auto a = sample(scene, {}, 7, 200), b = sample(scene, {}, 7, 200),
             c = sample(scene, {}, 8, 200);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.area_m2, b.area_m2);
  EXPECT_NE(a.points, c.points);
}

TEST(SurfaceSampler, RefusesMoreThanMaxPoints) {
  const auto r = sample_surfaces(room(), {}, {.density_per_m2 = 1e6, .max_points = 1'000'000});
  ASSERT_FALSE(r);
  // 98 m2 of floor, ceiling and walls: 9.8e7 points
  EXPECT_NE(r.error().find("1000000 points/m2 over 98.0 m2"), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("9.8e+07 points, more than the limit of 1000000"), std::string::npos)
      << r.error();
  EXPECT_NE(r.error().find("a density of at most 10204 points/m2"), std::string::npos) << r.error();
  EXPECT_FALSE(sample_surfaces(room(), {}, {.density_per_m2 = 0}));
  EXPECT_FALSE(sample_surfaces(room(), {}, {.density_per_m2 = std::nan("")}));
}

// a 1 x 1 m square at z = 1 of two triangles, facing +z (or -z when flipped)
TriangleMesh square(bool flipped) {
  TriangleMesh m;
  m.vertices = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  if (flipped)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

TEST(SurfaceSampler, MeshTrianglesFollowTheirWinding) {
  const SceneSpec scene = room(false, false);
  const double floor = 24;
  for (const bool flipped : {false, true}) {
    const auto s = sample(scene, {square(flipped)});
    size_t on_mesh = 0;
    for (size_t i = 0; i < s.points.size(); ++i) {
      if (std::abs(s.points[i][2] - 1) > 1e-6) continue;
      ++on_mesh;
      ASSERT_EQ(s.normals[i][2], flipped ? -1.0f : 1.0f);
      ASSERT_TRUE(s.points[i][0] >= 0 && s.points[i][0] <= 1 && s.points[i][1] >= 0 &&
                  s.points[i][1] <= 1);
    }
    EXPECT_NEAR(static_cast<double>(on_mesh), kDensity, 3 * std::sqrt(kDensity));
    // a mesh is no solid: the floor under it stays
    EXPECT_NEAR(s.area_m2, floor + 1, 3 * std::sqrt((floor + 1) * kDensity) / kDensity);
  }
}

TEST(SurfaceSampler, MeshPointsInsideSolidsOrOutsideTheBoundsAreDropped) {
  SceneSpec scene = room(false, false);
  // covers x in [0.75, 1.25] of the square
  scene.boxes.push_back({.name = "cover", .center_m = {1, 0.5, 1}, .size_m = {0.5, 2, 0.5}});
  TriangleMesh outside = square(false);
  for (auto& v : outside.vertices) v.z = 3;  // above the bounds
  const auto s = sample(scene, {square(false), outside});
  size_t on_mesh = 0;
  for (const auto& p : s.points) {
    ASSERT_LT(p[2], 2.5f + kHiddenTolerance);
    if (std::abs(p[2] - 1) < 1e-6 && p[0] < 0.75 - 1e-4) ++on_mesh;
    ASSERT_FALSE(std::abs(p[2] - 1) < 1e-6 && p[0] > 0.75 && p[0] < 1.25 && p[1] > 0 && p[1] < 1)
        << "mesh point inside the box";
  }
  EXPECT_NEAR(static_cast<double>(on_mesh), 0.75 * kDensity, 3 * std::sqrt(0.75 * kDensity));
}

// A closed unit cube on the floor of an open room, with a partition inside it at z = 0.5.
// Kept: the floor around the cube, the cube's top and sides (5 m2). Left out by the
// visibility test: the partition and the floor under the cube; by the floor: the cube's base.
TEST(SurfaceSampler, WhatAMeshClosesInIsLeftOut) {
  const SceneSpec scene = room(false, false);
  TriangleMesh partition = square(false);
  for (auto& v : partition.vertices) v.z = 0.5;
  for (const bool flipped : {false, true}) {
    const auto s = sample(scene, {test::cube(flipped), partition});
    EXPECT_NEAR(s.area_m2, 24 - 1 + 5, 3 * std::sqrt(28 * kDensity) / kDensity);
    for (const auto& p : s.points) {
      const bool inside =
          p[0] > 1e-3 && p[0] < 1 - 1e-3 && p[1] > 1e-3 && p[1] < 1 - 1e-3 && p[2] < 1 - 1e-3;
      ASSERT_FALSE(inside) << p[0] << " " << p[1] << " " << p[2] << " flipped " << flipped;
    }
  }
  // with the test off, as before it: the partition and the floor under the cube stay
  auto off = sample_surfaces(scene, {test::cube(), partition},
                             {.density_per_m2 = kDensity, .visibility_rays = 0});
  ASSERT_TRUE(off);
  EXPECT_NEAR(off->area_m2, 24 + 5 + 1, 3 * std::sqrt(30 * kDensity) / kDensity);
}

TEST(SurfaceSampler, WhatAnOpenMeshShowsStays) {
  TriangleMesh partition = square(false);
  for (auto& v : partition.vertices) v.z = 0.5;
  const auto s = sample(room(false, false), {test::cube(false, true), partition});
  // the partition, seen from above through the open top, and the four sides (seen from
  // outside) stay; the floor under the partition is closed in
  EXPECT_NEAR(s.area_m2, 24 - 1 + 4 + 1, 3 * std::sqrt(28 * kDensity) / kDensity);
}

TEST(SurfaceSampler, RefusesANegativeVisibilityRayCount) {
  const auto r = sample_surfaces(room(), {}, {.density_per_m2 = 10, .visibility_rays = -1});
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("visibility_rays"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace scancrew::sim
