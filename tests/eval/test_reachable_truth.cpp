#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "eval/reachable_truth.hpp"

namespace scancrew::eval {
namespace {

using msg::Vec3;

sim::SceneSpec scene_of(const std::string& yaml) {
  auto scene = sim::parse_scene(yaml, "reach.yaml", ".");
  EXPECT_TRUE(scene) << (scene ? "" : scene.error().front());
  return scene ? *scene : sim::SceneSpec{};
}

// The scene's ground truth at a low density, and which points a robot observes.
struct Case {
  sim::SurfaceSamples truth;
  ReachableTruth result;
  std::vector<Vec3> poses;
};

Case run(const sim::SceneSpec& scene, const FreeSpaceBody& body, const std::vector<Vec3>& starts,
         const ObserverModel& observer = {}, double density = 100) {
  Case c;
  sim::SamplingOptions sampling;
  sampling.density_per_m2 = density;
  auto truth = sim::sample_surfaces(scene, {}, sampling);
  EXPECT_TRUE(truth) << truth.error();
  c.truth = *truth;
  const sim::SceneSolids solids(scene, {});
  auto fs = FreeSpace::build(solids, scene, body, starts);
  EXPECT_TRUE(fs) << fs.error();
  auto result = reachable_truth(c.truth.points, c.truth.normals, solids, *fs, observer);
  EXPECT_TRUE(result) << result.error();
  c.result = *result;
  c.poses = fs->reachable_positions(body.kind == robot::RobotKind::kGround ? 0.5 : 1.0);
  return c;
}

// The fraction of the points that `select` picks that are observable, and how many it picks.
std::pair<double, size_t> fraction(const Case& c,
                                   const std::function<bool(const Vec3&, const Vec3&)>& select) {
  size_t picked = 0, seen = 0;
  for (size_t i = 0; i < c.truth.points.size(); ++i) {
    const auto& p = c.truth.points[i];
    const auto& n = c.truth.normals[i];
    if (!select({p[0], p[1], p[2]}, {n[0], n[1], n[2]})) continue;
    ++picked;
    seen += c.result.observable[i];
  }
  return {picked == 0 ? 0.0 : static_cast<double>(seen) / static_cast<double>(picked), picked};
}

// A 5 m tall box (2 x 2 m) in a 20 x 20 m yard, a ground robot starting 2 m from its -x face.
sim::SceneSpec tall_box_yard() {
  return scene_of(R"(
name: yard
bounds_min_m: [-10, -10, 0]
bounds_max_m: [10, 10, 6]
boxes:
  - {name: tower, center_m: [3, 0, 2.5], size_m: [2, 2, 5]}
)");
}

TEST(ReachableTruth, AGroundRobotSeesATallBoxsNearFacesButNotItsTopNorItsUpperPart) {
  const Case c = run(tall_box_yard(), default_body(robot::RobotKind::kGround), {{-2, 0, 0}});
  const auto [top, top_n] =
      fraction(c, [](const Vec3& p, const Vec3& n) { return n.z > 0.9 && p.z > 4.9; });
  EXPECT_GT(top_n, 300u);
  EXPECT_EQ(top, 0.0);
  // a level camera 0.35 m up sees at most 0.35 + 5 tan 30° = 3.24 m high within its 5 m range
  const auto [upper, upper_n] =
      fraction(c, [](const Vec3& p, const Vec3& n) { return n.z < 0.5 && p.z > 3.3; });
  EXPECT_GT(upper_n, 300u);
  EXPECT_EQ(upper, 0.0);
  const auto [near, near_n] =
      fraction(c, [](const Vec3& p, const Vec3& n) { return n.x < -0.9 && p.z < 1.5; });
  EXPECT_GT(near_n, 200u);
  EXPECT_GT(near, 0.97);
  // the yard's floor within a few metres of the box: seen
  const auto [floor, floor_n] = fraction(c, [](const Vec3& p, const Vec3& n) {
    return n.z > 0.9 && p.z < 0.01 && std::abs(p.x) < 5 && std::abs(p.y) < 5 && p.x < 1.5;
  });
  EXPECT_GT(floor_n, 1000u);
  EXPECT_GT(floor, 0.97);
}

TEST(ReachableTruth, TheUpperPartOfATallWallIsBeyondTheFieldOfView) {
  const sim::SceneSpec scene = scene_of(R"(
name: hall
bounds_min_m: [-4, -4, 0]
bounds_max_m: [4, 4, 5]
wall_height_m: 5
)");
  const Case c = run(scene, default_body(robot::RobotKind::kGround), {{0, 0, 0}});
  // 8 m across: the far side of the hall is 7.4 m away at most, so the walls are seen up to
  // 0.35 + 5 tan 30° = 3.24 m, from 5 m away
  const auto [low, low_n] =
      fraction(c, [](const Vec3& p, const Vec3& n) { return n.z == 0 && p.z < 1.5; });
  EXPECT_GT(low_n, 1000u);
  EXPECT_GT(low, 0.97);
  const auto [high, high_n] =
      fraction(c, [](const Vec3& p, const Vec3& n) { return n.z == 0 && p.z > 3.3; });
  EXPECT_GT(high_n, 1000u);
  EXPECT_EQ(high, 0.0);
}

TEST(ReachableTruth, ARoomBehindAClosedDoorIsUnobservable) {
  const sim::SceneSpec scene = scene_of(R"(
name: two_rooms
bounds_min_m: [-5, -2.5, 0]
bounds_max_m: [5, 2.5, 2]
wall_height_m: 2
ceiling: true
boxes:
  - {name: door, center_m: [0, 0, 1], size_m: [0.2, 5, 2]}
)");
  const Case c = run(scene, default_body(robot::RobotKind::kGround), {{-3, 0, 0}});
  const auto [behind, behind_n] = fraction(c, [](const Vec3& p, const Vec3&) { return p.x > 0.1; });
  EXPECT_GT(behind_n, 3000u);
  EXPECT_EQ(behind, 0.0);
  const auto [floor, floor_n] =
      fraction(c, [](const Vec3& p, const Vec3& n) { return n.z > 0.9 && p.x < -0.5; });
  EXPECT_GT(floor_n, 1000u);
  EXPECT_GT(floor, 0.97);
}

TEST(ReachableTruth, AMultirotorInItsBandSeesTheTopOfABox) {
  const sim::SceneSpec scene = scene_of(R"(
name: yard
bounds_min_m: [-8, -8, 0]
bounds_max_m: [8, 8, 8]
boxes:
  - {name: block, center_m: [0, 0, 1.5], size_m: [2, 2, 3]}
)");
  FreeSpaceBody uav = default_body(robot::RobotKind::kMultirotor);
  uav.max_altitude_m = 7;
  ObserverModel camera;
  camera.camera_up_m = 0;
  const Case c = run(scene, uav, {{-5, 0, 3}}, camera);
  const auto [top, top_n] =
      fraction(c, [](const Vec3& p, const Vec3& n) { return n.z > 0.9 && p.z > 2.9; });
  EXPECT_GT(top_n, 300u);
  EXPECT_GT(top, 0.97);
  // the same box seen by a ground robot: not its top
  const Case g = run(scene, default_body(robot::RobotKind::kGround), {{-5, 0, 0}});
  EXPECT_EQ(fraction(g, [](const Vec3& p, const Vec3& n) { return n.z > 0.9 && p.z > 2.9; }).first,
            0.0);
}

// The buckets, the cache and the ray cap agree with trying every lattice position on every
// point (the plain reference): they may only miss a few points, never add one.
TEST(ReachableTruth, AgreesWithTryingEveryPoseOnEveryPoint) {
  const sim::SceneSpec scene = scene_of(R"(
name: clutter
bounds_min_m: [-5, -5, 0]
bounds_max_m: [5, 5, 3]
wall_height_m: 3
boxes:
  - {name: a, center_m: [1, 1, 0.5], size_m: [1, 2, 1], yaw_deg: 30}
  - {name: b, center_m: [-2, 2, 1], size_m: [0.5, 0.5, 2]}
  - {name: c, center_m: [2, -2, 0.3], size_m: [3, 0.4, 0.6]}
cylinders:
  - {name: d, center_m: [-2, -2, 1.5], radius_m: 0.4, height_m: 3}
)");
  const ObserverModel o;
  const Case c = run(scene, default_body(robot::RobotKind::kGround), {{-4, 0, 0}}, o, 30);
  const sim::SceneSolids solids(scene, {});
  const double half_fov = 0.5 * o.fov_v_deg * std::numbers::pi / 180;
  size_t reference = 0, missed = 0;
  for (size_t i = 0; i < c.truth.points.size(); ++i) {
    const auto& pf = c.truth.points[i];
    const auto& nf = c.truth.normals[i];
    const Vec3 p{pf[0], pf[1], pf[2]};
    bool seen = false;
    for (const Vec3& b : c.poses) {
      const double heading = std::atan2(p.y - b.y, p.x - b.x);
      const Vec3 cam{b.x + o.camera_forward_m * std::cos(heading),
                     b.y + o.camera_forward_m * std::sin(heading), b.z + o.camera_up_m};
      const double depth = std::hypot(p.x - cam.x, p.y - cam.y);
      const double elevation = std::atan2(p.z - cam.z, depth);
      // either side of the surface: the line of sight rules out the back of a solid's face
      const double facing =
          std::abs(nf[0] * (cam.x - p.x) + nf[1] * (cam.y - p.y) + nf[2] * (cam.z - p.z));
      if (std::hypot(p.x - b.x, p.y - b.y) < o.camera_forward_m || depth < o.min_range_m ||
          depth > o.max_range_m || std::abs(elevation) > half_fov || facing <= 0)
        continue;
      if (!solids.segment_blocked(cam, p, ReachableTruthOptions{}.end_margin_m)) {
        seen = true;
        break;
      }
    }
    reference += seen ? 1 : 0;
    EXPECT_TRUE(seen || c.result.observable[i] == 0) << i;
    missed += seen && c.result.observable[i] == 0 ? 1 : 0;
  }
  EXPECT_GT(reference, c.truth.points.size() / 2);
  EXPECT_LT(static_cast<double>(missed), 0.005 * static_cast<double>(reference));
  EXPECT_EQ(c.result.observable_count + missed, reference);
}

// A mesh triangle whose winding points away from the robot: seen from its back unless the
// normals are trusted.
TEST(ReachableTruth, AMeshSurfaceIsSeenFromEitherSideUnlessNormalsAreTrusted) {
  const sim::SceneSpec scene = scene_of(R"(
name: sheet
bounds_min_m: [-5, -5, 0]
bounds_max_m: [5, 5, 3]
)");
  const io::TriangleMesh sheet{.vertices = {{2, -2, 0}, {2, 2, 0}, {2, 0, 2}},
                               .triangles = {{0, 1, 2}}};
  const sim::SceneSolids solids(scene, {sheet});
  auto fs = FreeSpace::build(solids, scene, default_body(robot::RobotKind::kGround), {{-2, 0, 0}});
  ASSERT_TRUE(fs) << fs.error();
  const std::vector<std::array<float, 3>> points = {{2, 0, 0.5}, {2, 1, 0.3}};
  const std::vector<std::array<float, 3>> away = {{1, 0, 0}, {1, 0, 0}};  // towards +x
  auto either = reachable_truth(points, away, solids, *fs, {});
  ASSERT_TRUE(either) << either.error();
  EXPECT_EQ(either->observable_count, 2u);  // from x < 2
  ReachableTruthOptions trusted;
  trusted.trust_normals = true;
  auto one = reachable_truth(points, away, solids, *fs, {}, trusted);
  ASSERT_TRUE(one) << one.error();
  // from x > 2 only, round the sheet's ends: the sheet is 4 m wide at the floor, the yard 10 m
  EXPECT_EQ(one->observable_count, 2u);
  // walls close the yard at the sheet's ends: nothing reaches its +x side
  sim::SceneSpec closed = scene;
  closed.boxes.push_back({.name = "left", .center_m = {2, -3.5, 1}, .size_m = {0.2, 3, 2}});
  closed.boxes.push_back({.name = "right", .center_m = {2, 3.5, 1}, .size_m = {0.2, 3, 2}});
  const sim::SceneSolids closed_solids(closed, {sheet});
  auto closed_fs = FreeSpace::build(closed_solids, closed, default_body(robot::RobotKind::kGround),
                                    {{-2, 0, 0}});
  ASSERT_TRUE(closed_fs) << closed_fs.error();
  EXPECT_EQ(reachable_truth(points, away, closed_solids, *closed_fs, {}, trusted)->observable_count,
            0u);
  EXPECT_EQ(reachable_truth(points, away, closed_solids, *closed_fs, {})->observable_count, 2u);
}

TEST(ReachableTruth, ObservableSamplesKeepTheSeenPointsAndTheirShareOfTheArea) {
  sim::SurfaceSamples truth;
  truth.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  truth.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  truth.area_m2 = 8;
  const sim::SurfaceSamples kept = observable_samples(truth, {1, 0, 0, 1});
  ASSERT_EQ(kept.points.size(), 2u);
  EXPECT_EQ(kept.points[1][0], 3.0f);
  EXPECT_DOUBLE_EQ(kept.area_m2, 4);
}

}  // namespace
}  // namespace scancrew::eval
