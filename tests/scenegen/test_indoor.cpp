// The indoor grammar (scenegen/indoor.cpp): sizes and heights in the ranges, what
// is drawn, and the passages it promises (at least 1.2 m wide, nothing solid in them).

#include <gtest/gtest.h>

#include <algorithm>

#include "scenegen_fixtures.hpp"

namespace scancrew::scenegen {
namespace {

using testing::bottom;
using testing::generated;
using testing::starts_with;
using testing::top;

TEST(IndoorGrammar, FloorsAre15To40MetresASideWithWalls2To5MetresTall) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const sim::SceneSpec s = generated(Family::kIndoor, seed).scene;
    SCOPED_TRACE(seed);
    for (double side : {s.max_m.x - s.min_m.x, s.max_m.y - s.min_m.y}) {
      EXPECT_GE(side, 15.0 - 1e-9);
      EXPECT_LE(side, 40.0 + 1e-9);
    }
    EXPECT_GE(s.wall_height_m, 2.0);
    EXPECT_LE(s.wall_height_m, 5.0);
    EXPECT_DOUBLE_EQ(s.max_m.z, s.wall_height_m);
  }
}

TEST(IndoorGrammar, MostFloorsAreSmallButTheWholeRangeIsReachable) {
  int small = 0;
  double least = 100, most = 0;
  for (uint64_t seed = 1; seed <= 100; ++seed) {
    const sim::SceneSpec s = generated(Family::kIndoor, seed).scene;
    const double a = s.max_m.x - s.min_m.x, b = s.max_m.y - s.min_m.y;
    small += std::max(a, b) <= 25.0 + 1e-9;
    least = std::min({least, a, b});
    most = std::max({most, a, b});
  }
  EXPECT_GE(small, 55);
  EXPECT_LT(least, 16.0);
  EXPECT_GT(most, 34.0);
}

TEST(IndoorGrammar, EveryFloorHasRoomsDoorwaysAGalleryWithColumnsPillarsAndBoxes) {
  int with_corridor = 0, with_ceiling = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const GeneratedScene c = generated(Family::kIndoor, seed);
    SCOPED_TRACE(seed);
    const auto count = [&](Passage::Kind k) {
      return std::count_if(c.passages.begin(), c.passages.end(),
                           [&](const Passage& p) { return p.kind == k; });
    };
    EXPECT_GE(count(Passage::Kind::kDoorway), 2);  // at least three rooms
    EXPECT_GE(count(Passage::Kind::kGallery), 1);
    EXPECT_GE(count(Passage::Kind::kColonnadeGap), 1);
    with_corridor += count(Passage::Kind::kCorridor) > 0;
    with_ceiling += c.scene.ceiling;
    const auto named = [&](const std::string& prefix) {
      return std::count_if(c.scene.boxes.begin(), c.scene.boxes.end(),
                           [&](const auto& b) { return starts_with(b.name, prefix); }) +
             std::count_if(c.scene.cylinders.begin(), c.scene.cylinders.end(),
                           [&](const auto& y) { return starts_with(y.name, prefix); });
    };
    EXPECT_GE(named("pillar_") + named("box_"), 3);
    EXPECT_GE(named("lintel_"), 2);
    EXPECT_TRUE(c.scene.meshes.empty());  // the project's own geometry only
  }
  EXPECT_GE(with_corridor, 3);
  EXPECT_GE(with_ceiling, 3);
  EXPECT_LE(with_ceiling, 17);
}

// what the generator promises: doorways, corridors, gaps between columns and the space
// under a gallery at least 1.2 m wide, and no solid in them from the floor up to their
// clear height (at least 0.6 m: a ground robot passes under)
TEST(IndoorGrammar, PassagesAreAtLeast1_2MetresWideAndClear) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const GeneratedScene c = generated(Family::kIndoor, seed);
    for (const Passage& p : c.passages) {
      SCOPED_TRACE(std::to_string(seed) + " " + p.name + " (" + to_string(p.kind) + ")");
      EXPECT_GE(p.width_m, 1.2 - 1e-9);
      EXPECT_GE(std::max(p.area.width(), p.area.depth()), p.width_m - 1e-9);
      if (p.kind != Passage::Kind::kColonnadeGap) {
        EXPECT_GE(std::min(p.area.width(), p.area.depth()),
                  p.kind == Passage::Kind::kDoorway ? 0.1 : p.width_m - 1e-9);
      }
      EXPECT_GE(p.clear_height_m, 0.6);
      for (const auto& b : c.scene.boxes)
        if (bottom(b) < p.clear_height_m - 1e-9) {
          EXPECT_FALSE(overlaps(footprint(b).grown(-1e-6), p.area)) << b.name;
        }
      for (const auto& y : c.scene.cylinders)
        if (bottom(y) < p.clear_height_m - 1e-9) {
          EXPECT_FALSE(overlaps(footprint(y).grown(-1e-6), p.area)) << y.name;
        }
    }
  }
}

TEST(IndoorGrammar, FloatingBoxesLeaveAGroundRobotRoomUnderThemAndEverythingIsInside) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const sim::SceneSpec s = generated(Family::kIndoor, seed).scene;
    for (const auto& b : s.boxes) {
      SCOPED_TRACE(std::to_string(seed) + " " + b.name);
      if (bottom(b) > 1e-9) {
        EXPECT_GE(bottom(b), 0.6);
      }
      EXPECT_LE(top(b), s.max_m.z + 1e-9);
      const Rect f = footprint(b);
      EXPECT_GE(f.x0, s.min_m.x - 1e-6);
      EXPECT_LE(f.x1, s.max_m.x + 1e-6);
      EXPECT_GE(f.y0, s.min_m.y - 1e-6);
      EXPECT_LE(f.y1, s.max_m.y + 1e-6);
    }
  }
}

}  // namespace
}  // namespace scancrew::scenegen
