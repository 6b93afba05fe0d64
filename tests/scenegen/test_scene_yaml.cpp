// write_scene_yaml(): what it writes, sim::parse_scene reads back unchanged.

#include <gtest/gtest.h>

#include <cmath>

#include "scenegen_fixtures.hpp"

namespace scancrew::scenegen {
namespace {

void expect_same(const sim::SceneSpec& a, const sim::SceneSpec& b) {
  const auto near = [](const msg::Vec3& p, const msg::Vec3& q) {
    return std::abs(p.x - q.x) < 1e-9 && std::abs(p.y - q.y) < 1e-9 && std::abs(p.z - q.z) < 1e-9;
  };
  EXPECT_EQ(a.name, b.name);
  EXPECT_TRUE(near(a.min_m, b.min_m) && near(a.max_m, b.max_m));
  EXPECT_EQ(a.ceiling, b.ceiling);
  EXPECT_DOUBLE_EQ(a.wall_height_m, b.wall_height_m);
  EXPECT_DOUBLE_EQ(a.wall_thickness_m, b.wall_thickness_m);
  EXPECT_DOUBLE_EQ(a.dot_size_m, b.dot_size_m);
  EXPECT_EQ(a.texture_seed, b.texture_seed);
  ASSERT_EQ(a.boxes.size(), b.boxes.size());
  for (size_t i = 0; i < a.boxes.size(); ++i) {
    EXPECT_EQ(a.boxes[i].name, b.boxes[i].name);
    EXPECT_TRUE(near(a.boxes[i].center_m, b.boxes[i].center_m)) << a.boxes[i].name;
    EXPECT_TRUE(near(a.boxes[i].size_m, b.boxes[i].size_m)) << a.boxes[i].name;
    EXPECT_NEAR(a.boxes[i].yaw_rad, b.boxes[i].yaw_rad, 1e-9) << a.boxes[i].name;
  }
  ASSERT_EQ(a.cylinders.size(), b.cylinders.size());
  for (size_t i = 0; i < a.cylinders.size(); ++i) {
    EXPECT_EQ(a.cylinders[i].name, b.cylinders[i].name);
    EXPECT_TRUE(near(a.cylinders[i].center_m, b.cylinders[i].center_m));
    EXPECT_DOUBLE_EQ(a.cylinders[i].radius_m, b.cylinders[i].radius_m);
    EXPECT_DOUBLE_EQ(a.cylinders[i].height_m, b.cylinders[i].height_m);
  }
  for (auto [sa, sb] : {std::pair{&a.starts.ground, &b.starts.ground},
                        std::pair{&a.starts.multirotor, &b.starts.multirotor}}) {
    ASSERT_EQ(sa->size(), sb->size());
    for (size_t i = 0; i < sa->size(); ++i) {
      EXPECT_TRUE(near((*sa)[i].position_m, (*sb)[i].position_m));
      EXPECT_NEAR((*sa)[i].yaw_rad, (*sb)[i].yaw_rad, 1e-9);
    }
  }
}

TEST(SceneYaml, AHandMadeSceneReadsBackUnchanged) {
  sim::SceneSpec s;
  s.name = "hand_made";
  s.min_m = {-2, -1.5, 0};
  s.max_m = {2, 1.5, 2.5};
  s.wall_height_m = 2.5;
  s.wall_thickness_m = 0.2;
  s.ceiling = true;
  s.texture_seed = 12345678901234ull;
  s.boxes.push_back(
      {"crate", {0.5, -0.25, 0.375}, {0.6, 0.4, 0.75}, 30 * M_PI / 180, {0.8, 0.25, 0.2}});
  s.boxes.push_back({"lintel", {-1, 0, 2.2}, {0.15, 1.2, 0.6}, 0, {}});
  s.cylinders.push_back({"post", {-1.25, 1, 1.25}, 0.125, 2.5, {0.2, 0.2, 0.2}});
  s.starts.ground = {{{-1.5, -1, 0}, M_PI / 2}, {{1.5, 1, 0}, -M_PI}};
  s.starts.multirotor = {{{0, 0, 1.5}, 0}};
  const std::string text = write_scene_yaml(s, "a header\nof two lines");
  EXPECT_EQ(text.rfind("# a header\n# of two lines\nname: hand_made\n", 0), 0u) << text;
  auto back = sim::parse_scene(text, "hand_made.yaml", "/tmp");
  ASSERT_TRUE(back) << back.error().front();
  expect_same(s, *back);
  EXPECT_EQ(write_scene_yaml(*back, "a header\nof two lines"), text);
}

TEST(SceneYaml, GeneratedCandidatesOfBothFamiliesReadBackUnchanged) {
  for (Family f : {Family::kIndoor, Family::kOutdoor})
    for (uint64_t seed = 1; seed <= 5; ++seed) {
      SCOPED_TRACE(to_string(f) + " " + std::to_string(seed));
      Candidate c = testing::candidate(f, seed);
      c.scene.name = "candidate";
      Rng rng(seed);
      auto& starts = f == Family::kIndoor ? c.scene.starts.ground : c.scene.starts.multirotor;
      starts = choose_starts(c, rng, 6, 1.0, f == Family::kIndoor ? 0.0 : 2.0);
      EXPECT_EQ(starts.size(), 6u);
      const std::string text = write_scene_yaml(c.scene);
      auto back = sim::parse_scene(text, "candidate.yaml", "/tmp");
      ASSERT_TRUE(back) << back.error().front();
      expect_same(c.scene, *back);
      EXPECT_EQ(write_scene_yaml(*back), text);
    }
}

}  // namespace
}  // namespace scancrew::scenegen
