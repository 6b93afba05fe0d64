// The outdoor grammar (scenegen/outdoor.cpp): site sizes, buildings (count, heights,
// shapes), overhangs, pipe racks and towers, and the room left between them for a
// multirotor.

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "scenegen_fixtures.hpp"

namespace scancrew::scenegen {
namespace {

using testing::bottom;
using testing::generated;
using testing::starts_with;
using testing::top;

// "building_3_wing" -> "building_3"; "rack_1_post_2_1" -> "rack_1"; "tower_2_tank" -> "tower_2"
std::string object_of(const std::string& name) {
  const size_t first = name.find('_');
  const size_t second = name.find('_', first + 1);
  return name.substr(0, second);
}

TEST(OutdoorGrammar, SitesAre40To80MetresASideWithoutWallsOrCeiling) {
  double least = 100, most = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const sim::SceneSpec s = generated(Family::kOutdoor, seed).scene;
    SCOPED_TRACE(seed);
    for (double side : {s.max_m.x - s.min_m.x, s.max_m.y - s.min_m.y}) {
      EXPECT_GE(side, 40.0 - 1e-9);
      EXPECT_LE(side, 80.0 + 1e-9);
      least = std::min(least, side);
      most = std::max(most, side);
    }
    EXPECT_EQ(s.wall_height_m, 0.0);
    EXPECT_FALSE(s.ceiling);
    EXPECT_TRUE(s.meshes.empty());
  }
  EXPECT_LT(least, 45.0);
  EXPECT_GT(most, 65.0);
}

TEST(OutdoorGrammar, ThreeToEightBuildings4To20MetresTallOfVariedShapes) {
  std::set<std::string> shapes;
  int overhangs = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const GeneratedScene c = generated(Family::kOutdoor, seed);
    SCOPED_TRACE(seed);
    std::map<std::string, double> height;
    for (const auto& b : c.scene.boxes) {
      if (!starts_with(b.name, "building_")) continue;
      if (b.name.ends_with("_overhang")) {
        ++overhangs;
        EXPECT_GE(bottom(b), 3.0);
        continue;
      }
      const std::string id = object_of(b.name);
      height[id] = std::max(height[id], top(b));
      const std::string part = b.name.substr(id.size());
      shapes.insert(part.empty() ? "block" : part);
    }
    EXPECT_GE(height.size(), 3u);
    EXPECT_LE(height.size(), 8u);
    for (const auto& [id, h] : height) {
      EXPECT_GE(h, 4.0) << id;
      EXPECT_LE(h, 20.0) << id;
    }
  }
  EXPECT_TRUE(shapes.count("block") && shapes.count("_wing") && shapes.count("_tower"));
  EXPECT_GE(overhangs, 5);
}

TEST(OutdoorGrammar, PipeRacksAndTowersStandBesideTheBuildings) {
  int racks = 0, floating_pipes = 0, towers = 0, water_towers = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const GeneratedScene c = generated(Family::kOutdoor, seed);
    std::set<std::string> objects;
    for (const auto& b : c.scene.boxes) {
      objects.insert(object_of(b.name));
      floating_pipes += b.name.find("_pipe_") != std::string::npos && bottom(b) >= 3.0;
    }
    for (const auto& y : c.scene.cylinders) {
      objects.insert(object_of(y.name));
      water_towers += y.name.ends_with("_tank") && bottom(y) >= 8.0;
    }
    for (const auto& o : objects) {
      racks += starts_with(o, "rack_");
      towers += starts_with(o, "tower_");
    }
  }
  EXPECT_GE(racks, 20);  // one or two per site, where room is left
  EXPECT_GE(floating_pipes, 40);
  EXPECT_GE(towers, 20);
  EXPECT_GE(water_towers, 2);
}

// a multirotor (1 m sphere) passes between any two objects and between an object and the
// site's edge: footprints 4 m apart, 3 m from the edge
TEST(OutdoorGrammar, FootprintsLeaveAMultirotorPassage) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const GeneratedScene c = generated(Family::kOutdoor, seed);
    const sim::SceneSpec& s = c.scene;
    std::map<std::string, Rect> extent;
    const auto add = [&](const std::string& name, const Rect& r) {
      const std::string id = object_of(name);
      auto [it, fresh] = extent.emplace(id, r);
      if (!fresh)
        it->second = {std::min(it->second.x0, r.x0), std::min(it->second.y0, r.y0),
                      std::max(it->second.x1, r.x1), std::max(it->second.y1, r.y1)};
    };
    for (const auto& b : s.boxes) add(b.name, footprint(b));
    for (const auto& y : s.cylinders) add(y.name, footprint(y));
    for (const auto& [a, ra] : extent) {
      SCOPED_TRACE(std::to_string(seed) + " " + a);
      EXPECT_GE(ra.x0, s.min_m.x + 3.0 - 1e-6);
      EXPECT_LE(ra.x1, s.max_m.x - 3.0 + 1e-6);
      EXPECT_GE(ra.y0, s.min_m.y + 3.0 - 1e-6);
      EXPECT_LE(ra.y1, s.max_m.y - 3.0 + 1e-6);
      for (const auto& [b, rb] : extent)
        if (a < b) {
          EXPECT_GE(gap(ra, rb), 4.0 - 1e-6) << b;
        }
    }
    double highest = 0;
    for (const auto& b : s.boxes) highest = std::max(highest, top(b));
    for (const auto& y : s.cylinders) highest = std::max(highest, top(y));
    EXPECT_GE(s.max_m.z, highest + 2.0 - 1e-9);
  }
}

}  // namespace
}  // namespace scancrew::scenegen
