// The tsdf_mapper on the sim backend (mapper_harness.hpp): robots at rest send patches at
// doubling intervals, losing no evidence; bad parameters are refused, each named.

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

TEST(TsdfMapper, RobotsAtRestSendPatchesAtDoublingIntervalsLosingNoEvidence) {
  // two robots standing still for 30 s (150 images each, 30 patches' worth): a patch that
  // would neither change a voxel's state nor double a known voxel's evidence in the team's
  // estimate is held back, its images staying in the current patch, which goes out once it
  // doubles the evidence: after 5, 10, 20, 40 and 80 images (weights here are the same at
  // every image), and not after the last 70. What each robot holds grows as log2(time)
  std::string text = launch_text(30.0, R"(
  - name: mapper
    type: tsdf_mapper
    params: {mode: distributed, voxel_m: 0.1, truncation_m: 0.3}
)");
  const std::string moving = "vx: 0.4, yaw_rate: 0.18";
  text.replace(text.find(moving), moving.size(), "vx: 0, yaw_rate: 0");
  auto launch = run(text);
  ASSERT_TRUE(launch);
  auto m = mappers(*launch);
  ASSERT_EQ(m.size(), 2u);
  uint64_t made = 0;
  for (TsdfMapper* mapper : m) {
    const TsdfMapperStats& s = mapper->stats();
    EXPECT_EQ(s.integrated, 150u);
    EXPECT_EQ(s.patches_made, 5u);
    EXPECT_EQ(s.patches_held_back, 25u);
    std::printf("robot %u: %llu patches made, %llu held back\n", mapper->robot_id(),
                static_cast<unsigned long long>(s.patches_made),
                static_cast<unsigned long long>(s.patches_held_back));
    made += s.patches_made;
  }
  for (TsdfMapper* mapper : m) {
    EXPECT_EQ(mapper->held_patches().size(), made);
    EXPECT_EQ(mapper->stats().requests_sent, 0u);
    // a patch's index is its last image's stamp in ms (images every 200 ms here): the 5th,
    // 10th, 20th, 40th and 80th image
    std::vector<uint32_t> own;
    for (const uint64_t id : mapper->held_patches())
      if (id >> 32 == mapper->robot_id()) own.push_back(static_cast<uint32_t>(id));
    ASSERT_EQ(own.size(), 5u);
    for (size_t k = 1; k < own.size(); ++k)
      EXPECT_EQ(own[k] - own[0], 200u * ((5u << k) - 5u)) << "patch " << k;
  }
  // each robot's snapshot holds the team's patches and its own held-back images: the two
  // robots' maps cover the same voxels and agree in their states
  const MapDiff d = compare(*m[0]->snapshot(), *m[1]->snapshot());
  EXPECT_GT(d.compared, 1000u);
  EXPECT_EQ(d.missing, 0u);
  EXPECT_LE(d.state_differs, d.compared / 1000);
}

TEST(TsdfMapper, RefusesBadParameters) {
  auto launch = Launch::from_string(launch_text(1.0, R"(
  - {name: mapper, type: tsdf_mapper, params: {voxel_m: 0.1, truncation_m: 0.01, mode: sideways,
                                               depth_topic: /r1/depth}}
)"),
                                    "bad.yaml");
  ASSERT_FALSE(launch);
  std::string all;
  for (const std::string& e : launch.error()) all += e + "\n";
  EXPECT_NE(all.find("truncation_m"), std::string::npos) << all;
  EXPECT_NE(all.find("mode"), std::string::npos) << all;
  EXPECT_NE(all.find("depth_topic"), std::string::npos) << all;
}

}  // namespace
}  // namespace scancrew::tsdf_mapper
