// IsePipeline (thesis 2.4.2, 2.4.3, Definitions 1-4): the ISE set C, C_rem for ISEs no
// robot can inspect, viewpoints, clusters and gains on hand-built maps; completion once the
// last inspectable ISE is scanned; bad configurations refused with the parameter named.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/ise/ise_pipeline.hpp"
#include "tests/core/ise/scenes.hpp"
#include "tests/core/ise/voxel_scene.hpp"

namespace scancrew::ise {
namespace {

using test::key;
using test::Key;
using test::VoxelScene;
using tsdf::VoxelState;

IsePipeline make_pipeline(const IseConfig& config = test::pipeline_config()) {
  auto p = IsePipeline::create(config, test::kWth, test::kVoxelM);
  EXPECT_TRUE(p.has_value()) << p.error();
  return std::move(p).value();
}

std::set<Key> voxels_at(const IseResult& r, const std::vector<uint32_t>& ids) {
  std::set<Key> out;
  for (uint32_t i : ids) out.insert(key(r.ises[i].voxel));
  return out;
}

TEST(IsePipeline, UnreachableIsesFormTheRemainingSetAndGetNoCluster) {
  VoxelScene scene;
  test::build_room(scene);
  test::build_pocket(scene);
  const auto snap = scene.snapshot();
  IsePipeline pipeline = make_pipeline();
  const IseResult& r = pipeline.update(*snap);

  std::set<Key> all = test::kRoomIses;
  all.insert(test::kPocketIses.begin(), test::kPocketIses.end());
  EXPECT_EQ(test::voxels_of(r.ises), all);
  ASSERT_EQ(r.ises.size(), 8u);
  EXPECT_EQ(r.map_sequence, snap->sequence());

  // the pocket's own candidates are not feasible: there is no free space to stand in
  for (const Ise& ise : r.ises)
    if (test::kPocketIses.contains(key(ise.voxel))) {
      const auto c = candidate(ise, pipeline.config().robot_types[0]);
      ASSERT_TRUE(c.has_value());
      EXPECT_FALSE(feasible(*snap, pipeline.config().robot_types[0], c->position));
    }

  EXPECT_EQ(voxels_at(r, r.remaining), test::kPocketIses);
  EXPECT_EQ(r.inspectable_count, 2u);
  for (uint32_t i = 0; i < r.ises.size(); ++i)
    EXPECT_EQ(r.inspectable[i] == 1, test::kRoomIses.contains(key(r.ises[i].voxel)));

  // one viewpoint per room ISE, looking back at it, and none made for or seeing the pocket
  ASSERT_EQ(r.viewpoints.size(), 2u);
  std::set<Key> planned;
  for (const Viewpoint& v : r.viewpoints) {
    EXPECT_EQ(v.types, robot::kind_bit(RobotKind::kMultirotor));
    ASSERT_EQ(v.ises.size(), 1u);
    EXPECT_EQ(v.seen, v.ises);  // the middle gain ray sees its own ISE, nothing else
    planned.insert(key(r.ises[v.ises[0]].voxel));
    const Eigen::Vector3d to_ise = r.ises[v.ises[0]].center - v.position;
    EXPECT_NEAR(to_ise.norm(), 2.0, 1e-9);
    EXPECT_NEAR(v.look().dot(to_ise.normalized()), 1.0, 1e-9);
  }
  EXPECT_EQ(planned, test::kRoomIses);

  // 4.2 m apart: no neighbour within d_v = 2, each other's nearest within d_v^max = 5
  ASSERT_EQ(r.clusters.size(), 1u);
  const Cluster& c = r.clusters[0];
  EXPECT_EQ(c.viewpoints, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(voxels_at(r, c.seen), test::kRoomIses);
  EXPECT_DOUBLE_EQ(c.gain, 2.0 / 8);  // g(U) = |C_U| / |C|
  EXPECT_TRUE(c.centroid.isApprox(Eigen::Vector3d(-0.05, 0.05, 0.05)));
  EXPECT_FALSE(r.complete);
}

TEST(IsePipeline, CompletesOnlyAfterTheLastInspectableIseStaysScanned) {
  VoxelScene scene;
  test::build_room(scene);
  test::build_pocket(scene);
  IsePipeline pipeline = make_pipeline();  // completion_updates = 2
  EXPECT_FALSE(pipeline.update(*scene.snapshot()).complete);
  EXPECT_EQ(pipeline.result().inspectable_count, 2u);

  // the hole observed: its neighbours are scanned (Definition 3) and no longer ISEs
  scene.next_update();
  scene.set({-1, 0, 0}, VoxelState::kOccupied);
  const auto snap = scene.snapshot();
  EXPECT_TRUE(is_scanned(*snap, {0, 0, 0}));
  EXPECT_TRUE(is_scanned(*snap, {-2, 0, 0}));
  const IseResult& first = pipeline.update(*snap);
  EXPECT_EQ(first.inspectable_count, 0u);
  EXPECT_EQ(voxels_at(first, first.remaining), test::kPocketIses);  // C_rem stays
  EXPECT_TRUE(first.viewpoints.empty());
  EXPECT_TRUE(first.clusters.empty());
  EXPECT_FALSE(first.complete) << "complete after 1 of 2 updates";
  EXPECT_TRUE(pipeline.update(*snap).complete);
  EXPECT_TRUE(pipeline.update(*snap).complete);

  // a new hole: inspectable again, not complete
  scene.next_update();
  scene.set({-1, 2, 2}, VoxelState::kUnknown);
  const IseResult& again = pipeline.update(*scene.snapshot());
  EXPECT_EQ(again.inspectable_count, 2u);
  EXPECT_FALSE(again.complete);
}

// Visited and still incomplete (docs/ise.md): given-up ISEs join C_rem, lose their
// viewpoints, and the mission can complete without them; update() and full() agree.
TEST(IsePipeline, GivenUpIsesJoinTheRemainingSetAndLoseTheirViewpoints) {
  VoxelScene scene;
  test::build_room(scene);
  test::build_pocket(scene);
  IsePipeline pipeline = make_pipeline();  // completion_updates = 2
  const auto snap = scene.snapshot();
  const IseResult& before = pipeline.update(*snap);
  ASSERT_EQ(before.inspectable_count, 2u);
  ASSERT_FALSE(before.viewpoints.empty());
  std::vector<VoxelIndex> room;
  for (const Ise& ise : before.ises)
    if (test::kRoomIses.contains(key(ise.voxel))) room.push_back(ise.voxel);
  ASSERT_EQ(room.size(), 2u);

  // one of the two given up: the other keeps a viewpoint
  pipeline.give_up({room[0]});
  const IseResult& one = pipeline.update(*snap);
  EXPECT_EQ(one.inspectable_count, 1u);
  EXPECT_TRUE(voxels_at(one, one.remaining).contains(key(room[0])));
  ASSERT_FALSE(one.viewpoints.empty());
  for (const Viewpoint& v : one.viewpoints)
    for (uint32_t id : v.seen) EXPECT_NE(key(one.ises[id].voxel), key(room[0]));

  // both: no viewpoint, no cluster, complete after completion_updates
  pipeline.give_up({room[1]});
  const IseResult& both = pipeline.update(*snap);
  EXPECT_EQ(both.inspectable_count, 0u);
  EXPECT_EQ(both.remaining.size(), both.ises.size());
  EXPECT_TRUE(both.viewpoints.empty());
  EXPECT_TRUE(both.clusters.empty());
  EXPECT_FALSE(both.complete);
  EXPECT_TRUE(pipeline.update(*snap).complete);
  EXPECT_EQ(pipeline.full(*snap).inspectable_count, 0u);
  EXPECT_EQ(pipeline.given_up_count(), 2u);
}

TEST(IsePipeline, EmptyMapOrMapWithoutIsesNeverCompletes) {
  VoxelScene scene;
  IsePipeline pipeline = make_pipeline();
  for (int i = 0; i < 5; ++i) {
    const IseResult& r = pipeline.update(*scene.snapshot());
    EXPECT_TRUE(r.ises.empty());
    EXPECT_FALSE(r.complete) << "update " << i;
  }
  // observed, but no surface in it yet: still nothing to call finished
  scene.next_update();
  scene.fill({-10, -10, -10}, {10, 10, 10}, VoxelState::kEmpty);
  for (int i = 0; i < 5; ++i) {
    const IseResult& r = pipeline.update(*scene.snapshot());
    EXPECT_TRUE(r.ises.empty());
    EXPECT_FALSE(r.complete) << "update " << i;
  }
}

// --- configuration -----------------------------------------------------------------------

TEST(IsePipeline, IsesOutsideTheRegionAreLeftOut) {
  // the room's two ISEs lie at x = 0.05 and x = -0.15 m; a region from x = -0.1 m on keeps
  // the first only, and only its viewpoint; the incremental update agrees with full()
  VoxelScene scene;
  test::build_room(scene);
  IseConfig config = test::pipeline_config();
  config.region_min_m.x() = -0.1;
  IsePipeline pipeline = make_pipeline(config);
  const IseResult& r = pipeline.update(*scene.snapshot());
  ASSERT_EQ(r.ises.size(), 1u);
  EXPECT_EQ(key(r.ises[0].voxel), (Key{0, 0, 0}));
  EXPECT_EQ(r.inspectable_count, 1u);
  ASSERT_EQ(r.viewpoints.size(), 1u);
  EXPECT_GT(r.viewpoints[0].position.x(), 1.0);  // (2.05, 0.05, 0.05), facing -x

  scene.next_update();
  scene.set({-1, 0, 0}, VoxelState::kOccupied);  // the hole closed: no ISE at all
  const IseResult& after = pipeline.update(*scene.snapshot());
  EXPECT_TRUE(after.ises.empty());
  IsePipeline fresh = make_pipeline(config);
  EXPECT_TRUE(fresh.full(*scene.snapshot()).ises.empty());
}

TEST(IseConfigValidate, AnEmptyRegionIsNamed) {
  IseConfig c = test::pipeline_config();
  c.region_min_m = Eigen::Vector3d(0, 0, 0);
  c.region_max_m = Eigen::Vector3d(1, 1, 0);
  EXPECT_NE(c.validate(test::kWth, test::kVoxelM).find("region_min_m"), std::string::npos);
}

TEST(IseConfigValidate, AnEmptyAltitudeBandIsNamed) {
  IseConfig c = test::pipeline_config();
  c.robot_types[0].min_altitude_m = 5;
  c.robot_types[0].max_altitude_m = 1;
  EXPECT_NE(c.validate(test::kWth, test::kVoxelM).find("min_altitude_m"), std::string::npos);
}

TEST(IseConfigValidate, DefaultsAndTheTestConfigurationAreValid) {
  EXPECT_EQ(IseConfig{}.validate(0.3, 0.2), "");
  EXPECT_EQ(test::pipeline_config().validate(test::kWth, test::kVoxelM), "");
}

TEST(IseConfigValidate, DeltaPoseOutsideTheCameraRangeIsNamed) {
  IseConfig c = test::pipeline_config();
  c.robot_types[0].delta_pose_m = 6.0;  // range [0.3, 5]
  std::string problem = c.validate(test::kWth, test::kVoxelM);
  EXPECT_NE(problem.find("delta_pose_m"), std::string::npos) << problem;
  EXPECT_NE(problem.find("multirotor"), std::string::npos) << problem;
  c.robot_types[0].delta_pose_m = 0.2;
  problem = c.validate(test::kWth, test::kVoxelM);
  EXPECT_NE(problem.find("delta_pose_m"), std::string::npos) << problem;
  auto p = IsePipeline::create(c, test::kWth, test::kVoxelM);
  ASSERT_FALSE(p.has_value());
  EXPECT_NE(p.error().find("delta_pose_m"), std::string::npos) << p.error();
}

TEST(IseConfigValidate, DvAboveDvMaxIsNamed) {
  IseConfig c = test::pipeline_config();
  c.d_v_m = 3.0;
  c.d_v_max_m = 2.0;
  const std::string problem = c.validate(test::kWth, test::kVoxelM);
  EXPECT_NE(problem.find("d_v_m"), std::string::npos) << problem;
  EXPECT_NE(problem.find("d_v_max_m"), std::string::npos) << problem;
  auto p = IsePipeline::create(c, test::kWth, test::kVoxelM);
  ASSERT_FALSE(p.has_value());
  EXPECT_NE(p.error().find("d_v_max_m"), std::string::npos) << p.error();
}

TEST(IseConfigValidate, NonPositiveWeightThresholdIsNamed) {
  const IseConfig c = test::pipeline_config();
  for (double w_th : {0.0, -1.0}) {
    auto p = IsePipeline::create(c, w_th, test::kVoxelM);
    ASSERT_FALSE(p.has_value()) << "W_th " << w_th;
    EXPECT_NE(p.error().find("W_th"), std::string::npos) << p.error();
  }
}

TEST(IseConfigValidate, EveryProblemIsReportedAtOnce) {
  IseConfig c = test::pipeline_config();
  c.robot_types[0].delta_pose_m = 6.0;
  c.d_v_m = 3.0;
  c.d_v_max_m = 2.0;
  const std::string problem = c.validate(0.0, test::kVoxelM);
  EXPECT_NE(problem.find("W_th"), std::string::npos) << problem;
  EXPECT_NE(problem.find("delta_pose_m"), std::string::npos) << problem;
  EXPECT_NE(problem.find("d_v_max_m"), std::string::npos) << problem;
}

}  // namespace
}  // namespace scancrew::ise
