// generate(): deterministic per seed, and every scene it returns loads, has its free space
// connected for its robot kind and its starts free (eval/free_space.hpp, checked again here
// on the scene as read back from its file).

#include <gtest/gtest.h>

#include <cmath>

#include "eval/free_space.hpp"
#include "scenegen/scenegen.hpp"
#include "sim/scene_solids.hpp"

namespace scancrew::scenegen {
namespace {

std::string yaml_of(Family f, uint64_t seed) {
  auto g = generate(f, seed);
  EXPECT_TRUE(g) << (g ? "" : g.error());
  return g ? write_scene_yaml(g->scene, "header") : std::string();
}

TEST(Generate, TheSameSeedGivesTheSameBytes) {
  for (Family f : {Family::kIndoor, Family::kOutdoor}) {
    const std::string a = yaml_of(f, 3);
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, yaml_of(f, 3));
  }
}

TEST(Generate, DifferentSeedsGiveDifferentScenes) {
  for (Family f : {Family::kIndoor, Family::kOutdoor}) {
    const std::string a = yaml_of(f, 1), b = yaml_of(f, 2);
    // the names differ anyway: compare without them
    EXPECT_NE(a.substr(a.find("bounds_min_m")), b.substr(b.find("bounds_min_m")));
  }
}

TEST(Generate, FamiliesAreNamedAndAnUnknownOneIsRefused) {
  EXPECT_EQ(parse_family("indoor"), Family::kIndoor);
  EXPECT_EQ(parse_family("outdoor"), Family::kOutdoor);
  EXPECT_FALSE(parse_family("attic"));
  EXPECT_EQ(robot_kind(Family::kOutdoor), robot::RobotKind::kMultirotor);
}

class GenerateSeeds : public ::testing::TestWithParam<Family> {};

TEST_P(GenerateSeeds, ScenesOfSeeds1To10LoadAreConnectedAndStartFree) {
  const Family f = GetParam();
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE(to_string(f) + " " + std::to_string(seed));
    auto g = generate(f, seed);
    ASSERT_TRUE(g) << g.error();
    EXPECT_EQ(g->scene.name, to_string(f) + "_" + std::to_string(seed));
    EXPECT_TRUE(g->free_space.connected && g->free_space.starts_free);
    // read back from its file, and checked again
    auto scene = sim::parse_scene(write_scene_yaml(g->scene), "generated.yaml", ".");
    ASSERT_TRUE(scene) << scene.error().front();
    const auto& starts = f == Family::kIndoor ? scene->starts.ground : scene->starts.multirotor;
    ASSERT_GE(starts.size(), 5u);
    std::vector<msg::Vec3> points;
    for (const auto& s : starts) points.push_back(s.position_m);
    const sim::SceneSolids solids(*scene, {});
    auto space = eval::FreeSpace::build(solids, *scene, eval::default_body(robot_kind(f)), points);
    ASSERT_TRUE(space) << space.error();
    EXPECT_TRUE(space->connected());
    EXPECT_GT(space->free_cells(), 0u);
    for (size_t i = 0; i < points.size(); ++i) EXPECT_TRUE(space->start_free(i)) << i;
    // spread out: no two starts within 3 m
    for (size_t i = 0; i < points.size(); ++i)
      for (size_t j = i + 1; j < points.size(); ++j)
        EXPECT_GE(std::hypot(points[i].x - points[j].x, points[i].y - points[j].y), 3.0);
  }
}

INSTANTIATE_TEST_SUITE_P(BothFamilies, GenerateSeeds,
                         ::testing::Values(Family::kIndoor, Family::kOutdoor),
                         [](const auto& info) { return to_string(info.param); });

}  // namespace
}  // namespace scancrew::scenegen
