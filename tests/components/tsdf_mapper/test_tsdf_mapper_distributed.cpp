// The tsdf_mapper's distributed mode on the sim backend (mapper_harness.hpp): fusing patches
// equals integrating every frame into one map; two robots exchange every patch; a lost patch
// is recovered by request; a corrupt one is refused, then recovered; a lost teammate (kLost on
// its robot_state) is no holder: the nearest live one replies; a restarted robot takes back
// the patches its old process made.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "executors/launch.hpp"
#include "tests/components/tsdf_mapper/mapper_harness.hpp"

namespace scancrew::tsdf_mapper {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

TEST(TsdfMapper, FusedPatchesEqualOneMapOfEveryFrame) {
  // robot 1's depth into a single map and, in the same run, into patches of 5 frames
  auto launch = run(launch_text(10.0,
                                std::string(R"(
  - {name: single, type: tsdf_mapper, remap: {map: map_single}, params: {mode: single, )") +
                                    kMapParams + R"(}}
  - {name: patches, type: tsdf_mapper, params: {mode: distributed, )" +
                                    kMapParams + R"(}}
)",
                                R"(
  - {id: 1, namespace: r1, kind: ground, start: [0.0, -2.2, 0, 0]})"));
  ASSERT_TRUE(launch);
  auto m = mappers(*launch);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0]->stats().integrated, 50u);  // 10 s at 5 Hz
  EXPECT_EQ(m[1]->stats().integrated, 50u);
  EXPECT_EQ(m[1]->stats().patches_made, 10u);
  const auto single = m[0]->snapshot(), fused = m[1]->snapshot();
  EXPECT_GT(single->block_count(), 100u);
  EXPECT_EQ(single->block_count(), fused->block_count());
  const MapDiff d = compare(*single, *fused);
  EXPECT_GT(d.compared, 40000u);
  EXPECT_EQ(d.missing, 0u);
  // the weighted average is associative: what differs is the patches' quantisation on
  // the wire (distance μ/254, weight 0.24 %), which a voxel whose weight sum lies that
  // close to W_th may feel
  EXPECT_LT(d.max_distance, 0.3 / 254 * 1.01);
  EXPECT_LT(d.max_weight_rel, 0.005);
  EXPECT_LT(d.state_differs, d.compared / 1000);
  const MapDiff back = compare(*fused, *single);
  EXPECT_EQ(back.missing, 0u);
  // patches are compact on the wire
  const TsdfMapperStats& s = m[1]->stats();
  std::printf("patches: %llu, wire %.1f kB each, raw float blocks %.1f kB each (1/%.1f)\n",
              static_cast<unsigned long long>(s.patches_made),
              static_cast<double>(s.patch_wire_bytes) / 1e3 / static_cast<double>(s.patches_made),
              static_cast<double>(s.patch_raw_bytes) / 1e3 / static_cast<double>(s.patches_made),
              static_cast<double>(s.patch_raw_bytes) / static_cast<double>(s.patch_wire_bytes));
  EXPECT_LE(s.patch_wire_bytes * 10, s.patch_raw_bytes);
}

TEST(TsdfMapper, TwoRobotsExchangeEveryPatch) {
  auto launch = run(launch_text(8.0, kTwoRobots));
  ASSERT_TRUE(launch);
  auto m = mappers(*launch);
  ASSERT_EQ(m.size(), 2u);
  for (TsdfMapper* mapper : m) {
    EXPECT_EQ(mapper->stats().patches_made, 8u);  // 40 frames
    EXPECT_EQ(mapper->stats().patches_received, 8u);
    EXPECT_EQ(mapper->stats().requests_sent, 0u);
    EXPECT_EQ(mapper->held_patches().size(), 16u);
  }
  // both global estimates hold the same patches; each adds only its own current patch,
  // empty at the end (40 frames, patches of 5)
  const MapDiff d = compare(*m[0]->snapshot(), *m[1]->snapshot());
  EXPECT_GT(d.compared, 40000u);
  EXPECT_EQ(d.missing, 0u);
  EXPECT_EQ(d.max_distance, 0.0);  // the same patches, fused from the same bytes
  EXPECT_EQ(d.state_differs, 0u);
}

TEST(TsdfMapper, ALostPatchIsRecoveredByRequest) {
  // robot 1's patch 2 never arrives: robot 2 sees it in robot 1's list and asks for it
  auto launch = run_with_link("{drop_nth: 2}");
  ASSERT_TRUE(launch);
  auto m = mappers(*launch);
  ASSERT_EQ(m.size(), 2u);
  auto* link = launch->find_component<PatchLink>();  // robot 1's
  ASSERT_NE(link, nullptr);
  EXPECT_EQ(link->spoiled, 1);
  EXPECT_EQ(m[0]->stats().requests_sent, 0u);
  EXPECT_EQ(m[0]->stats().patches_received, 8u);
  EXPECT_GE(m[1]->stats().requests_sent, 1u);
  EXPECT_GE(m[0]->stats().replies_sent, 1u);
  EXPECT_EQ(m[1]->stats().patches_received, 8u);
  EXPECT_EQ(m[1]->held_patches().size(), 16u);
}

TEST(TsdfMapper, ACorruptPatchIsRefusedThenRecovered) {
  auto launch = run_with_link("{corrupt_nth: 1}");
  ASSERT_TRUE(launch);
  auto m = mappers(*launch);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[1]->stats().patches_rejected, 1u);
  EXPECT_GE(m[1]->stats().requests_sent, 1u);
  EXPECT_EQ(m[1]->stats().patches_received, 8u);
  // the recovered patch came late, but fusion does not depend on the order: same maps
  const MapDiff d = compare(*m[0]->snapshot(), *m[1]->snapshot());
  EXPECT_EQ(d.missing, 0u);
  EXPECT_EQ(d.state_differs, 0u);
  EXPECT_LT(d.max_distance, 1e-5);
}

TEST(TsdfMapper, ALostTeammateIsNoHolderTheNearestLiveOneReplies) {
  const std::string text = std::string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 3.5, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: ground, start: [10, 0, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [0, 0, 0, 0]}
  - {id: 3, namespace: r3, kind: ground, start: [9, 0, 0, 0]}
remap: {pose: pose_gt}
components:
  - {name: script, type: test_patch_holder_script, per_robot: false, process: robot}
  - name: mapper
    type: tsdf_mapper
    params: {mode: distributed, request_delay_s: 0.5, request_retry_s: 1.0, )") +
                           kMapParams + "}\n";
  auto launch = Launch::from_string(text, "tsdf_mapper_lost.yaml",
                                    LaunchOptions{.process = "robot", .robot_id = 2});
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  auto m = mappers(**launch);
  ASSERT_EQ(m.size(), 1u);  // robot 2's only
  EXPECT_EQ(m[0]->stats().patches_received, 3u);
  EXPECT_EQ(m[0]->held_patches(),
            (std::vector<uint64_t>{HolderScript::patch(0), HolderScript::patch(1),
                                   HolderScript::patch(2)}));
  const auto* script = (*launch)->find_component<HolderScript>();
  ASSERT_NE(script, nullptr);
  // 1 s: robot 3 holds P0 and is nearer to robot 1: robot 2 is silent; 2 s: robot 3 lost,
  // robot 2 answers P1; 3 s: robot 3 back: silent on P2, but P0 is asked again (robot 3's
  // answer did not come, as from a robot out of the asker's range): robot 2 relays it
  ASSERT_EQ(script->replies.size(), 2u);
  EXPECT_EQ(script->replies[0].first, 1u);
  EXPECT_GT(script->replies[0].second, 1.95);
  EXPECT_LT(script->replies[0].second, 2.5);
  EXPECT_EQ(script->replies[1].first, 0u);
  EXPECT_GT(script->replies[1].second, 2.95);
  EXPECT_EQ(m[0]->stats().replies_sent, 2u);
}

TEST(TsdfMapper, ARestartedRobotTakesBackThePatchesItsOldProcessMade) {
  const std::string text = std::string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 2.0, sim_step_s: 0.05}
robots:
  - {id: 2, namespace: r2, kind: ground, start: [0, 0, 0, 0]}
  - {id: 3, namespace: r3, kind: ground, start: [1, 0, 0, 0]}
remap: {pose: pose_gt}
components:
  - {name: script, type: test_patch_restart_script, per_robot: false, process: robot}
  - name: mapper
    type: tsdf_mapper
    params: {mode: distributed, request_delay_s: 0.5, request_retry_s: 1.0, )") +
                           kMapParams + "}\n";
  auto launch = Launch::from_string(text, "tsdf_mapper_restart.yaml",
                                    LaunchOptions{.process = "robot", .robot_id = 2});
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  auto m = mappers(**launch);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0]->held_patches(), RestartScript::listed());
  EXPECT_EQ(m[0]->stats().patches_received, 2u);
  EXPECT_EQ(m[0]->stats().duplicates, 0u);
}

}  // namespace
}  // namespace scancrew::tsdf_mapper
