// profile_misses (eval/missed_points.hpp) on a plane at z = 0 whose distances are known:
// points at set heights above and below it fall in the near / off / hole bands, their
// normals in the up / side / down rows; an empty mesh makes holes; bad input is refused.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "eval/missed_points.hpp"

namespace scancrew::eval {
namespace {

using Vec3f = std::array<float, 3>;
constexpr double kEmax = 0.25;

// two triangles over [0, 10]² at z = 0
io::TriangleMesh square() {
  io::TriangleMesh m;
  m.vertices = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

TEST(ProfileMisses, DistanceToTheMeshGivesTheBandAndTheNormalTheFacing) {
  // heights: 0.1 (within e_max: near), 0.4 and 0.5 (near, <= 2 e_max), 0.7 and 0.99 (off,
  // <= 4 e_max), 1.2 and 3 (hole); below the plane the same distances
  const std::vector<Vec3f> points{{5, 5, 0.1F},  {5, 5, 0.4F}, {5, 5, 0.5F},   {5, 5, 0.7F},
                                  {5, 5, 0.99F}, {5, 5, 1.2F}, {5, 5, -0.45F}, {5, 5, -3}};
  const std::vector<Vec3f> normals{{0, 0, 1}, {0, 0, 2},     {1, 0, 0},  {0.5F, 0, 0.9F},
                                   {0, 1, 0}, {0, 1.2F, -1}, {0, 0, -1}, {-1, 0, 0}};
  const auto r = profile_misses(square(), points, normals, kEmax);
  ASSERT_TRUE(r.has_value()) << r.error();
  EXPECT_EQ(r->points, 8U);
  EXPECT_DOUBLE_EQ(r->e_max_m, kEmax);
  EXPECT_EQ(r->count(Facing::kUp, MissBand::kNear), 2U);    // 0.1, 0.4
  EXPECT_EQ(r->count(Facing::kSide, MissBand::kNear), 1U);  // 0.5
  EXPECT_EQ(r->count(Facing::kUp, MissBand::kOff), 1U);     // 0.7, normal 29 deg off +z
  EXPECT_EQ(r->count(Facing::kSide, MissBand::kOff), 1U);   // 0.99
  EXPECT_EQ(r->count(Facing::kSide, MissBand::kHole), 2U);  // 1.2 (50 deg off -z), -3
  EXPECT_EQ(r->count(Facing::kDown, MissBand::kNear), 1U);  // -0.45
  EXPECT_EQ(r->band_total(MissBand::kNear), 4U);
  EXPECT_EQ(r->band_total(MissBand::kOff), 2U);
  EXPECT_EQ(r->band_total(MissBand::kHole), 2U);
  EXPECT_EQ(r->facing_total(Facing::kUp), 3U);
  EXPECT_EQ(r->facing_total(Facing::kSide), 4U);
  EXPECT_EQ(r->facing_total(Facing::kDown), 1U);
}

TEST(ProfileMisses, PointsBesideTheMeshAreMeasuredToItsEdge) {
  // 0.4 m beyond the square's edge, level with it: near; 2 m beyond: a hole
  const std::vector<Vec3f> points{{10.4F, 5, 0}, {12, 5, 0}};
  const std::vector<Vec3f> normals{{1, 0, 0}, {1, 0, 0}};
  const auto r = profile_misses(square(), points, normals, kEmax);
  ASSERT_TRUE(r.has_value()) << r.error();
  EXPECT_EQ(r->count(Facing::kSide, MissBand::kNear), 1U);
  EXPECT_EQ(r->count(Facing::kSide, MissBand::kHole), 1U);
}

TEST(ProfileMisses, AnEmptyMeshMakesHolesAndNoPointsAnEmptyProfile) {
  const std::vector<Vec3f> points{{5, 5, 0}};
  const std::vector<Vec3f> normals{{0, 0, -1}};
  const auto holes = profile_misses(io::TriangleMesh{}, points, normals, kEmax);
  ASSERT_TRUE(holes.has_value()) << holes.error();
  EXPECT_EQ(holes->count(Facing::kDown, MissBand::kHole), 1U);

  const auto none = profile_misses(square(), {}, {}, kEmax);
  ASSERT_TRUE(none.has_value()) << none.error();
  EXPECT_EQ(none->points, 0U);
  EXPECT_EQ(none->band_total(MissBand::kHole), 0U);
}

TEST(ProfileMisses, BadInputIsRefusedWithTheCulpritNamed) {
  const std::vector<Vec3f> one{{5, 5, 1}};
  const std::vector<Vec3f> up{{0, 0, 1}};
  const std::vector<Vec3f> zero{{0, 0, 0}};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Vec3f> not_finite{{5, nan, 1}};

  auto r = profile_misses(square(), one, up, 0.0);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("e_max"), std::string::npos) << r.error();
  r = profile_misses(square(), one, {}, kEmax);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("normals"), std::string::npos) << r.error();
  r = profile_misses(square(), one, zero, kEmax);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("normal 0"), std::string::npos) << r.error();
  r = profile_misses(square(), not_finite, up, kEmax);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("point 0"), std::string::npos) << r.error();
  io::TriangleMesh broken = square();
  broken.triangles.push_back({0, 1, 7});
  r = profile_misses(broken, one, up, kEmax);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("triangle 2"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace scancrew::eval
