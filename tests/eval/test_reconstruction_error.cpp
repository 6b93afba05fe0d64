// Reconstruction error on planes and boxes whose errors are known in closed form.

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "eval/reconstruction_error.hpp"

namespace scancrew::eval {
namespace {

using Vec3f = std::array<float, 3>;

struct Samples {
  std::vector<Vec3f> points, normals;
};

constexpr double kEmax = 0.1 * 0.86602540378443864676;  // r_v·√3/2 for r_v = 0.1 m

// n × n quads (two triangles each) over [0, size_m] × [0, width_m] at height z_m.
io::TriangleMesh plane(double size_m, int n, double z_m, double width_m = -1) {
  if (width_m < 0) width_m = size_m;
  io::TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.push_back({width_m * i / n, size_m * j / n, z_m});
  const auto at = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

// A k × k grid of points at the centres of the cells of [0, size_m]² on z = 0, normal (0,0,nz).
Samples plane_points(double size_m, int k, float nz = 1) {
  Samples s;
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      s.points.push_back({static_cast<float>(size_m * (i + 0.5) / k),
                          static_cast<float>(size_m * (j + 0.5) / k), 0});
      s.normals.push_back({0, 0, nz});
    }
  return s;
}

// The box [-h, h]³ as 12 triangles wound outwards.
io::TriangleMesh box(double h) {
  io::TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({(i & 1) != 0 ? h : -h, (i & 2) != 0 ? h : -h, (i & 4) != 0 ? h : -h});
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

// n random points on each face of the box [-h, h]³, outward normals; seeded.
Samples box_points(double h, int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-h, h);
  Samples s;
  for (int axis = 0; axis < 3; ++axis)
    for (const double side : {-1.0, 1.0})
      for (int i = 0; i < n; ++i) {
        std::array<double, 3> p{u(rng), u(rng), u(rng)};
        p[static_cast<size_t>(axis)] = side * h;
        Vec3f normal{0, 0, 0};
        normal[static_cast<size_t>(axis)] = static_cast<float>(side);
        s.points.push_back(
            {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
        s.normals.push_back(normal);
      }
  return s;
}

Result<ReconstructionError, std::string> evaluate(const io::TriangleMesh& mesh, const Samples& s,
                                                  double e_max = kEmax, bool per_point = false) {
  return reconstruction_error(mesh, s.points, s.normals,
                              {.e_max_m = e_max, .per_point_error = per_point});
}

TEST(ReconstructionError, EmaxIsHalfTheVoxelDiagonal) {
  EXPECT_NEAR(max_error_for_voxel(0.2), 0.17320508, 1e-8);
  EXPECT_DOUBLE_EQ(max_error_for_voxel(0.1), kEmax);
}

TEST(ReconstructionError, APerfectPlaneCoversEverythingWithNoError) {
  const auto r = evaluate(plane(4, 8, 0), plane_points(4, 100));
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, EvalStatus::kOk);
  EXPECT_EQ(r->gt_points, 10000u);
  EXPECT_EQ(r->covered, 10000u);
  EXPECT_EQ(r->coverage, 1.0);
  EXPECT_NEAR(r->rmse_m, 0, 1e-9);
  EXPECT_EQ(r->mesh_triangles, 128u);
  EXPECT_EQ(r->e_max_m, kEmax);
}

TEST(ReconstructionError, APlaneOffsetAlongTheNormalGivesThatOffsetAsError) {
  const auto r = evaluate(plane(4, 8, 0.05), plane_points(4, 100));
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->coverage, 1.0);
  EXPECT_NEAR(r->mean_error_m, 0.05, 1e-9);
  EXPECT_NEAR(r->std_error_m, 0, 1e-9);
  EXPECT_NEAR(r->rmse_m, 0.05, 1e-9);
}

TEST(ReconstructionError, TheErrorIsPositiveOutsideTheSurfaceAndNegativeInside) {
  // outside: on the side the ground-truth normal points to
  const auto above = evaluate(plane(4, 8, 0.05), plane_points(4, 50));
  const auto below = evaluate(plane(4, 8, -0.05), plane_points(4, 50));
  // the same plane above, seen from ground truth facing down: now it is inside
  const auto flipped = evaluate(plane(4, 8, 0.05), plane_points(4, 50, -1));
  ASSERT_TRUE(above && below && flipped);
  EXPECT_NEAR(above->mean_error_m, 0.05, 1e-9);
  EXPECT_NEAR(below->mean_error_m, -0.05, 1e-9);
  EXPECT_NEAR(flipped->mean_error_m, -0.05, 1e-9);
  EXPECT_NEAR(below->rmse_m, 0.05, 1e-9);
}

TEST(ReconstructionError, AnInflatedBoxIsOutsideAndADeflatedBoxInside) {
  const Samples s = box_points(1.0, 2000, 7);
  const auto exact = evaluate(box(1.0), s);
  const auto inflated = evaluate(box(1.05), s);
  // near an edge of the deflated box, the nearest point is on that edge (up to 0.0866 m away),
  // but the error along the normal is still -0.05
  const auto deflated = evaluate(box(0.95), s);
  ASSERT_TRUE(exact && inflated && deflated);
  EXPECT_EQ(exact->coverage, 1.0);
  EXPECT_NEAR(exact->rmse_m, 0, 1e-6);  // float points
  EXPECT_EQ(inflated->coverage, 1.0);
  EXPECT_NEAR(inflated->mean_error_m, 0.05, 1e-6);
  EXPECT_NEAR(inflated->std_error_m, 0, 1e-6);
  EXPECT_EQ(deflated->coverage, 1.0);
  EXPECT_NEAR(deflated->mean_error_m, -0.05, 1e-6);
  EXPECT_NEAR(deflated->rmse_m, 0.05, 1e-6);
}

TEST(ReconstructionError, ASurfaceFartherThanEmaxCoversNothing) {
  const auto r = evaluate(plane(4, 8, 0.2), plane_points(4, 100));
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, EvalStatus::kNothingCovered);
  EXPECT_EQ(r->covered, 0u);
  EXPECT_EQ(r->coverage, 0.0);
  // undefined, not 0: a 0 would read as a perfect reconstruction
  EXPECT_TRUE(std::isnan(r->mean_error_m) && std::isnan(r->std_error_m) && std::isnan(r->rmse_m));
}

TEST(ReconstructionError, HalfASurfaceCoversHalfItsPointsPlusABandOfEmax) {
  // the mesh spans x in [0, 2] of the 4 m square; points up to e_max past its edge count too
  const auto r = evaluate(plane(4, 8, 0, 2.0), plane_points(4, 200));
  ASSERT_TRUE(r) << r.error();
  EXPECT_NEAR(r->coverage, 0.5 + kEmax / 4, 0.005);
  EXPECT_NEAR(r->rmse_m, 0, 1e-9);
}

TEST(ReconstructionError, TheNearestOfTwoSurfacesCounts) {
  io::TriangleMesh two = plane(4, 4, 0.03);
  const io::TriangleMesh lower = plane(4, 4, -0.05);
  const auto base = static_cast<uint32_t>(two.vertices.size());
  two.vertices.insert(two.vertices.end(), lower.vertices.begin(), lower.vertices.end());
  for (const auto& t : lower.triangles)
    two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  const auto r = evaluate(two, plane_points(4, 50));
  ASSERT_TRUE(r) << r.error();
  EXPECT_NEAR(r->mean_error_m, 0.03, 1e-9);
}

TEST(ReconstructionError, PointsAreCoveredUpToEmaxInAnyDirection) {
  io::TriangleMesh t;
  t.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  t.triangles = {{0, 1, 2}};
  Samples s;
  s.points = {{0.5F, -0.08F, 0}, {0.5F, -0.09F, 0}, {-0.03F, -0.04F, 0}, {0.2F, 0.2F, 0.06F}};
  s.normals = {{0, 1, 0}, {0, 1, 0}, {-0.6F, -0.8F, 0}, {0, 0, 1}};
  const auto r = evaluate(t, s, kEmax, true);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->point_error_m.size(), 4u);
  EXPECT_NEAR(r->point_error_m[0], 0.08, 1e-6);   // beyond an edge, facing it: outside
  EXPECT_TRUE(std::isnan(r->point_error_m[1]));   // 0.09 m > e_max
  EXPECT_NEAR(r->point_error_m[2], -0.05, 1e-6);  // beyond a vertex, facing away: inside
  EXPECT_NEAR(r->point_error_m[3], -0.06, 1e-6);  // above the face, facing up: inside
  EXPECT_EQ(r->covered, 3u);
}

TEST(ReconstructionError, GivesTheSameFiguresOnOneThreadAsOnMany) {
  const Samples s = box_points(1.0, 20000, 3);
  const io::TriangleMesh m = box(1.02);
  const auto many = evaluate(m, s, kEmax, true);
  tbb::task_arena one(1);
  Result<ReconstructionError, std::string> single = make_unexpected(std::string("not run"));
  one.execute([&] { single = evaluate(m, s, kEmax, true); });
  ASSERT_TRUE(many && single);
  EXPECT_EQ(std::bit_cast<uint64_t>(many->mean_error_m),
            std::bit_cast<uint64_t>(single->mean_error_m));
  EXPECT_EQ(std::bit_cast<uint64_t>(many->std_error_m),
            std::bit_cast<uint64_t>(single->std_error_m));
  EXPECT_EQ(many->covered, single->covered);
  ASSERT_EQ(many->point_error_m.size(), single->point_error_m.size());
  EXPECT_EQ(std::memcmp(many->point_error_m.data(), single->point_error_m.data(),
                        many->point_error_m.size() * sizeof(float)),
            0);
}

TEST(ReconstructionError, AnEmptyMeshCoversNothing) {
  const auto r = evaluate(io::TriangleMesh{}, plane_points(4, 10));
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, EvalStatus::kEmptyMesh);
  EXPECT_EQ(to_string(r->status), "empty mesh");
  EXPECT_EQ(r->coverage, 0.0);
  EXPECT_EQ(r->gt_points, 100u);
  EXPECT_TRUE(std::isnan(r->rmse_m));
}

void expect_refused(const Result<ReconstructionError, std::string>& r, const std::string& part) {
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find(part), std::string::npos) << r.error();
}

TEST(ReconstructionError, RefusesBadInputsNamingTheCulprit) {
  const Samples s = plane_points(4, 10);
  io::TriangleMesh m = plane(4, 2, 0);
  for (const double e : {0.0, -0.1, std::nan("")})
    expect_refused(evaluate(m, s, e), "e_max must be positive and finite");

  m.vertices[3].y = std::nan("");
  expect_refused(evaluate(m, s), "mesh vertex 3 is not finite (0, nan, 0)");
  m = plane(4, 2, 0);
  m.triangles[5][1] = 99;
  expect_refused(evaluate(m, s), "mesh triangle 5 refers to vertex 99 of 9");

  m = plane(4, 2, 0);
  expect_refused(evaluate(m, Samples{}), "no ground-truth points");
  Samples bad = s;
  bad.normals.pop_back();
  expect_refused(evaluate(m, bad), "100 ground-truth points but 99 normals");
  bad = s;
  bad.normals[7] = {0, 0, 0};
  expect_refused(evaluate(m, bad), "ground-truth normal 7 is zero or not finite (0, 0, 0)");
  bad = s;
  bad.points[8][2] = std::numeric_limits<float>::infinity();
  expect_refused(evaluate(m, bad), "ground-truth point 8 is not finite");
}

}  // namespace
}  // namespace scancrew::eval
