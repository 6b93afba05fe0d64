// The grid against a brute-force search over every triangle, and the closest point on a
// triangle in each of its Voronoi regions.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "eval/triangle_grid.hpp"

namespace scancrew::eval {
namespace {

double distance(const Point3& a, const Point3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

TEST(ClosestPointOnTriangle, ProjectsOntoTheFeatureOfTheRegionHoldingThePoint) {
  const Point3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  const auto near = [&](const Point3& p, const Point3& expected) {
    const Point3 q = closest_point_on_triangle(p, a, b, c);
    EXPECT_LT(distance(q, expected), 1e-12)
        << "p (" << p[0] << ", " << p[1] << ", " << p[2] << ") gave (" << q[0] << ", " << q[1]
        << ", " << q[2] << ")";
  };
  near({0.2, 0.3, 0.5}, {0.2, 0.3, 0});  // face
  near({-1, -1, 0.1}, a);                // vertices
  near({2, -0.5, 0}, b);
  near({-0.1, 3, -1}, c);
  near({0.5, -2, 0}, {0.5, 0, 0});  // edges
  near({-2, 0.25, 1}, {0, 0.25, 0});
  near({1, 1, 0}, {0.5, 0.5, 0});
  // a degenerate triangle is a segment
  const Point3 q = closest_point_on_triangle({0.5, 1, 0}, a, b, {0.5, 0, 0});
  EXPECT_LT(distance(q, {0.5, 0, 0}), 1e-12);
}

// A random soup of small triangles in a 2 m cube, and points around it.
struct Soup {
  io::TriangleMesh mesh;
  std::vector<Point3> points;
};

Soup soup(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> in_cube(0, 2), offset(-0.15, 0.15);
  Soup s;
  for (uint32_t t = 0; t < 300; ++t) {
    const msg::Vec3 centre{in_cube(rng), in_cube(rng), in_cube(rng)};
    for (int i = 0; i < 3; ++i)
      s.mesh.vertices.push_back(
          {centre.x + offset(rng), centre.y + offset(rng), centre.z + offset(rng)});
    s.mesh.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  // one large triangle across the cube: listed in many cells, filtered by distance
  const auto base = static_cast<uint32_t>(s.mesh.vertices.size());
  s.mesh.vertices.insert(s.mesh.vertices.end(), {{0, 0, 0}, {2, 0.3, 2}, {0.2, 2, 1.5}});
  s.mesh.triangles.push_back({base, base + 1, base + 2});
  std::uniform_real_distribution<double> around(-0.2, 2.2);
  for (int i = 0; i < 3000; ++i) s.points.push_back({around(rng), around(rng), around(rng)});
  return s;
}

std::optional<NearestPoint> brute_force(const io::TriangleMesh& m, const Point3& p, double r) {
  std::optional<NearestPoint> best;
  for (uint32_t t = 0; t < m.triangles.size(); ++t) {
    const auto v = [&](int i) {
      const msg::Vec3& x = m.vertices[m.triangles[t][i]];
      return Point3{x.x, x.y, x.z};
    };
    const Point3 q = closest_point_on_triangle(p, v(0), v(1), v(2));
    const double d = distance(p, q);
    if (d <= r && (!best || d < best->distance_m)) best = NearestPoint{t, d, q};
  }
  return best;
}

TEST(TriangleGrid, FindsWhatABruteForceSearchFinds) {
  for (const size_t max_cells : {TriangleGrid::kDefaultMaxCells, size_t{8}}) {
    const Soup s = soup(11);
    const auto grid = TriangleGrid::build(s.mesh, 0.1, max_cells);
    ASSERT_TRUE(grid) << grid.error();
    EXPECT_LE(grid->cells(), std::max<size_t>(max_cells, 1));
    size_t found = 0;
    for (const Point3& p : s.points) {
      const auto expected = brute_force(s.mesh, p, 0.1);
      const auto got = grid->nearest(p);
      ASSERT_EQ(got.has_value(), expected.has_value()) << "max_cells " << max_cells;
      if (!got) continue;
      ++found;
      EXPECT_EQ(got->triangle, expected->triangle);
      EXPECT_DOUBLE_EQ(got->distance_m, expected->distance_m);
    }
    EXPECT_GT(found, 300u);  // the comparison is not vacuous
  }
}

TEST(TriangleGrid, UsesCellsTwiceTheRadiusUnlessThatMakesTooMany) {
  const Soup s = soup(5);
  const auto fine = TriangleGrid::build(s.mesh, 0.1);
  const auto coarse = TriangleGrid::build(s.mesh, 0.1, 1000);
  ASSERT_TRUE(fine && coarse);
  EXPECT_EQ(fine->cell_size_m(), 0.2);
  EXPECT_GT(coarse->cell_size_m(), 0.2);
  EXPECT_LE(coarse->cells(), 1000u);
}

// 20,000 triangles that each spanned the whole scene (a 260 KB PLY) took 150 s in scancrew eval:
// the build's work is bounded before it starts.
TEST(TriangleGrid, TrianglesFarLargerThanTheRadiusAreRefusedBeforeTheWork) {
  io::TriangleMesh mesh;
  mesh.vertices = {{-50, -50, 0},  {50, -50, 0}, {0, 50, 0},
                   {-50, -50, 20}, {50, 50, 20}, {0, 50, 1}};
  for (int i = 0; i < 20000; ++i) mesh.triangles.push_back({0u, 1u, 2u});
  mesh.triangles.push_back({3u, 4u, 5u});
  const auto grid = TriangleGrid::build(mesh, 0.1);  // (before: minutes; the test's timeout)
  ASSERT_FALSE(grid);
  EXPECT_NE(grid.error().find("far larger than the search radius"), std::string::npos)
      << grid.error();
  // the same triangles at a radius of their own scale are fine
  mesh.triangles.resize(2);
  EXPECT_TRUE(TriangleGrid::build(mesh, 5.0));
}

TEST(TriangleGrid, AnEmptyMeshFindsNothingAndABadRadiusIsRefused) {
  const auto empty = TriangleGrid::build({}, 0.1);
  ASSERT_TRUE(empty);
  EXPECT_FALSE(empty->nearest({0, 0, 0}));
  const auto bad = TriangleGrid::build({}, -1);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("radius must be positive"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace scancrew::eval
