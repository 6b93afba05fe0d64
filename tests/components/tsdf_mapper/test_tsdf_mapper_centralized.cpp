// The tsdf_mapper's centralized mode on the sim backend (mapper_harness.hpp): a station's
// mapper integrates every robot's depth, from the simulator or from each robot's named depth
// topic.

#include <gtest/gtest.h>

#include <string>

#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "executors/launch.hpp"
#include "tests/components/tsdf_mapper/mapper_harness.hpp"

namespace scancrew::tsdf_mapper {

using tsdf::VoxelState;
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

TEST(TsdfMapper, ACentralizedMapperIntegratesEveryRobot) {
  auto launch = run(launch_text(4.0, std::string(R"(
  - {name: station, type: tsdf_mapper, per_robot: false, params: {mode: centralized, )") +
                                         kMapParams + "}}\n"));
  ASSERT_TRUE(launch);
  auto m = mappers(*launch);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0]->stats().integrated, 40u);  // 2 robots, 4 s at 5 Hz
  EXPECT_EQ(m[0]->stats().snapshots, 40u);
  // what each robot saw first (1.2 m ahead of its start) is mapped as free space
  const auto snap = m[0]->snapshot();
  EXPECT_EQ(snap->state_at({1.2, -2.2, 0.3}), VoxelState::kEmpty);
  EXPECT_EQ(snap->state_at({-1.2, 2.2, 0.3}), VoxelState::kEmpty);
}

TEST(TsdfMapper, ACentralizedMapperReadsEachRobotsDepthTopic) {
  // the station reads /<ns>/depth_masked, the depth_masks' output, not the simulator's depth
  auto launch = run(launch_text(4.0, std::string(R"(
  - {name: mask, type: depth_mask}
  - {name: station, type: tsdf_mapper, per_robot: false,
     params: {mode: centralized, depth_topic: depth_masked, )") +
                                         kMapParams + "}}\n"));
  ASSERT_TRUE(launch);
  auto m = mappers(*launch);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0]->stats().integrated, 40u);
  const auto snap = m[0]->snapshot();
  EXPECT_EQ(snap->state_at({1.2, -2.2, 0.3}), VoxelState::kEmpty);
  EXPECT_EQ(snap->state_at({-1.2, 2.2, 0.3}), VoxelState::kEmpty);
}

}  // namespace
}  // namespace scancrew::tsdf_mapper
