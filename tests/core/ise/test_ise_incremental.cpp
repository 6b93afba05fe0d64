// IsePipeline::update() after a prior update equals a fresh pipeline's full() on the same
// snapshot: ISEs, C_rem, viewpoints (pose, types, ISEs, C_q), clusters (members, C_U,
// gain), over a sequence of edits that each exercise one part of the incremental path.

#include <gtest/gtest.h>

#include <string>

#include "core/ise/ise_pipeline.hpp"
#include "tests/core/ise/scenes.hpp"
#include "tests/core/ise/voxel_scene.hpp"

namespace scancrew::ise {
namespace {

using test::VoxelScene;
using tsdf::VoxelState;

IsePipeline make_pipeline() {
  auto p = IsePipeline::create(test::pipeline_config(), test::kWth, test::kVoxelM);
  EXPECT_TRUE(p.has_value()) << p.error();
  return std::move(p).value();
}

// Exact equality: both paths run the same arithmetic in the same order.
void expect_same(const IseResult& inc, const IseResult& full, const std::string& step) {
  SCOPED_TRACE(step);
  EXPECT_EQ(inc.map_sequence, full.map_sequence);
  ASSERT_EQ(inc.ises.size(), full.ises.size());
  for (size_t i = 0; i < full.ises.size(); ++i) {
    EXPECT_EQ(inc.ises[i].voxel, full.ises[i].voxel) << "ISE " << i;
    EXPECT_EQ(inc.ises[i].direction, full.ises[i].direction) << "ISE " << i;
  }
  EXPECT_EQ(inc.inspectable, full.inspectable);
  EXPECT_EQ(inc.remaining, full.remaining);
  EXPECT_EQ(inc.inspectable_count, full.inspectable_count);
  ASSERT_EQ(inc.viewpoints.size(), full.viewpoints.size());
  for (size_t i = 0; i < full.viewpoints.size(); ++i) {
    const Viewpoint& a = inc.viewpoints[i];
    const Viewpoint& b = full.viewpoints[i];
    EXPECT_EQ(a.position, b.position) << "viewpoint " << i;
    EXPECT_EQ(a.yaw_rad, b.yaw_rad) << "viewpoint " << i;
    EXPECT_EQ(a.type, b.type) << "viewpoint " << i;
    EXPECT_EQ(a.types, b.types) << "viewpoint " << i;
    EXPECT_EQ(a.ises, b.ises) << "viewpoint " << i;
    EXPECT_EQ(a.seen, b.seen) << "viewpoint " << i;
  }
  ASSERT_EQ(inc.clusters.size(), full.clusters.size());
  for (size_t i = 0; i < full.clusters.size(); ++i) {
    const Cluster& a = inc.clusters[i];
    const Cluster& b = full.clusters[i];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.types, b.types) << "cluster " << i;
    EXPECT_EQ(a.viewpoints, b.viewpoints) << "cluster " << i;
    EXPECT_EQ(a.seen, b.seen) << "cluster " << i;
    EXPECT_EQ(a.gain, b.gain) << "cluster " << i;
    EXPECT_EQ(a.centroid, b.centroid) << "cluster " << i;
  }
  EXPECT_EQ(inc.complete, full.complete);
}

// Compares the running pipeline's update() with a fresh pipeline's full(); returns the
// incremental result's stats.
IseStats check_step(IsePipeline& running, const VoxelScene& scene, const std::string& step) {
  const auto snap = scene.snapshot();
  const IseResult& inc = running.update(*snap);
  IsePipeline fresh = make_pipeline();
  expect_same(inc, fresh.full(*snap), step);
  return inc.stats;
}

// Whether some viewpoint was made for the ISE at voxel v (lists it in its ises).
bool planned_for(const IseResult& r, const VoxelIndex& v) {
  for (const Viewpoint& vp : r.viewpoints)
    for (uint32_t i : vp.ises)
      if (r.ises[i].voxel == v) return true;
  return false;
}

size_t total_seen(const IseResult& r) {
  size_t n = 0;
  for (const Viewpoint& v : r.viewpoints) n += v.seen.size();
  return n;
}

TEST(IsePipelineIncremental, UpdateEqualsFullAfterEachEdit) {
  VoxelScene scene;
  test::build_room(scene);
  test::build_pocket(scene);
  IsePipeline running = make_pipeline();
  const size_t blocks = scene.blocks().size();
  EXPECT_TRUE(check_step(running, scene, "first update").full);

  // an unknown curtain at x = 1.0 m between the front viewpoint and the wall (no ISE:
  // nothing occupied near it): the viewpoint keeps its pose, so only the invalidation of
  // cached C_q makes it see less; then the curtain observed as empty again
  EXPECT_EQ(total_seen(running.result()), 2u);
  scene.next_update();
  scene.fill({10, -4, -4}, {10, 4, 4}, VoxelState::kUnknown);
  IseStats s = check_step(running, scene, "curtain");
  EXPECT_EQ(running.result().viewpoints.size(), 2u);
  EXPECT_EQ(total_seen(running.result()), 1u);
  scene.next_update();
  scene.fill({10, -4, -4}, {10, 4, 4}, VoxelState::kEmpty);
  s = check_step(running, scene, "curtain gone");
  EXPECT_EQ(total_seen(running.result()), 2u);

  // two more holes, in two blocks; the wall is flat around each, so all three holes'
  // ISEs on one side look along the same direction, close together: their viewpoints merge
  scene.next_update();
  scene.set({-1, 2, 0}, VoxelState::kUnknown);
  scene.set({-1, 3, -2}, VoxelState::kUnknown);
  s = check_step(running, scene, "holes opened");
  EXPECT_FALSE(s.full);
  EXPECT_EQ(s.changed_blocks, 2u);
  EXPECT_LT(s.dirty_blocks, blocks);
  EXPECT_EQ(running.result().ises.size(), 6u + 6u);
  EXPECT_LT(running.result().viewpoints.size(), running.result().stats.candidates);

  // an obstacle at the candidates of (0, 0, 0) and (0, 2, 0), 2 m along +x in block
  // (2, 0, 0): two blocks from the ISEs' own block, so only the feasibility recheck sees it
  EXPECT_TRUE(planned_for(running.result(), {0, 0, 0}));
  scene.next_update();
  scene.set({20, 0, 2}, VoxelState::kOccupied);
  s = check_step(running, scene, "obstacle at a viewpoint");
  EXPECT_FALSE(s.full);
  EXPECT_FALSE(planned_for(running.result(), {0, 0, 0}));
  EXPECT_FALSE(planned_for(running.result(), {0, 2, 0}));
  EXPECT_TRUE(planned_for(running.result(), {0, 3, -2}));

  // the obstacle gone again
  scene.next_update();
  scene.set({20, 0, 2}, VoxelState::kEmpty);
  check_step(running, scene, "obstacle removed");
  EXPECT_TRUE(planned_for(running.result(), {0, 0, 0}));

  // a write far from every viewpoint's view: their C_q are reused
  scene.next_update();
  scene.set({45, 45, 45}, VoxelState::kOccupied);
  s = check_step(running, scene, "far write");
  EXPECT_EQ(s.visibility_computed, 0u);
  EXPECT_EQ(s.visibility_reused, running.result().viewpoints.size());
  EXPECT_GT(s.visibility_reused, 0u);

  // the first hole closed: its ISEs scanned
  scene.next_update();
  scene.set({-1, 0, 0}, VoxelState::kOccupied);
  check_step(running, scene, "hole closed");

  // a block holding ISEs removed from the map (its voxels unknown again)
  scene.next_update();
  scene.erase_block({-1, 0, 0});
  check_step(running, scene, "block with ISEs erased");

  // unchanged snapshot again
  check_step(running, scene, "no change");
}

TEST(IsePipelineIncremental, UpdateEqualsFullAfterABlockWithoutIsesIsErased) {
  VoxelScene scene;
  test::build_room(scene);
  IsePipeline running = make_pipeline();
  check_step(running, scene, "first update");
  // block (−1,−1,−1) holds part of the wall and no ISE; once it is gone, the empty voxels
  // beside it that still touch the rest of the wall become ISEs, e.g. (0, −1, −1)
  scene.next_update();
  scene.erase_block({-1, -1, -1});
  const auto snap = scene.snapshot();
  ASSERT_TRUE(is_ise(*snap, {0, -1, -1}));
  check_step(running, scene, "block without ISEs erased");
  EXPECT_TRUE(test::voxels_of(running.result().ises).contains({0, -1, -1}));
}

}  // namespace
}  // namespace scancrew::ise
