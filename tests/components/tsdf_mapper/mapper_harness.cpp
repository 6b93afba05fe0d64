// The tsdf_mapper tests' harness (mapper_harness.hpp): the test components' registrations,
// the launch text, the runs and the map comparison.

#include "tests/components/tsdf_mapper/mapper_harness.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/components/constant_driver.hpp"

namespace scancrew::tsdf_mapper::testing {

using tsdf::Block;
using tsdf::BlockIndex;
using tsdf::kBlockVoxels;
using tsdf::state_of;
using tsdf::Voxel;

SCANCREW_REGISTER_COMPONENT(PatchLink, "test_patch_link")
SCANCREW_REGISTER_COMPONENT(HolderScript, "test_patch_holder_script")
SCANCREW_REGISTER_COMPONENT(RestartScript, "test_patch_restart_script")

std::string launch_text(double duration_s, const std::string& mappers, const std::string& robots) {
  return R"(
clock: sim
executor: {type: step}
run: {duration_s: )" +
         std::to_string(duration_s) + R"(, sim_step_s: 0.05}
robots:)" +
         robots + R"(
remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params:
      scene: )" SCANCREW_SOURCE_DIR R"(/launch_cfg/scenes/test_arena.yaml
      publish_stereo: false
      depth_noise: false
  - {name: driver, type: test_constant_driver, params: {vx: 0.4, yaw_rate: 0.18}}
)" + mappers;
}

std::unique_ptr<Launch> run(const std::string& text) {
  auto launch = Launch::from_string(text, "tsdf_mapper_test.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  if (!launch) return nullptr;
  auto l = std::move(launch).value();
  l->run();
  return l;
}

std::vector<TsdfMapper*> mappers(const Launch& launch) {
  std::vector<TsdfMapper*> out;
  for (const auto& c : launch.components())
    if (auto* m = dynamic_cast<TsdfMapper*>(c.get())) out.push_back(m);
  return out;
}

MapDiff compare(const MapSnapshot& a, const MapSnapshot& b) {
  MapDiff d;
  for (const auto& [index, block] : a.blocks()) {
    const Block* other = b.block(index);
    for (int i = 0; i < kBlockVoxels; ++i) {
      const Voxel& va = block->voxels[static_cast<size_t>(i)];
      if (va.weight == 0) continue;
      ++d.compared;
      if (other == nullptr) {
        ++d.missing;
        continue;
      }
      const Voxel& vb = other->voxels[static_cast<size_t>(i)];
      const auto w_th = static_cast<float>(a.config().w_th);
      if (state_of(va, w_th) != state_of(vb, w_th)) ++d.state_differs;
      d.max_distance =
          std::max(d.max_distance, static_cast<double>(std::abs(va.distance_m - vb.distance_m)));
      d.max_weight_rel = std::max(d.max_weight_rel,
                                  static_cast<double>(std::abs(va.weight - vb.weight) / va.weight));
    }
  }
  return d;
}

const std::string kTwoRobots = std::string(R"(
  - name: mapper
    type: tsdf_mapper
    params: {mode: distributed, request_delay_s: 0.5, request_retry_s: 1.0, )") +
                               kMapParams + "}\n";

std::unique_ptr<Launch> run_with_link(const std::string& link_params) {
  std::string text = launch_text(
      8.0, kTwoRobots +
               "  - {name: link, type: test_patch_link, remap: {in: patch_raw, out: patch}, "
               "params: " +
               link_params + "}\n");
  const std::string from = "  - name: mapper\n    type: tsdf_mapper\n";
  text.replace(text.find(from), from.size(), from + "    remap: {patch: patch_raw}\n");
  return run(text);
}

bool one_voxel_patch(uint64_t id, int block_z, msg::TsdfPatch& out) {
  TsdfConfig config;
  config.voxel_m = 0.1;
  config.truncation_m = 0.3;
  config.max_weight = 100000;
  TsdfMap map(config);
  map.touch(BlockIndex(0, 0, block_z)).at(1, 2, 3) = Voxel{.distance_m = 0.05f, .weight = 2.0f};
  out = msg::TsdfPatch{};
  out.patch_id = id;
  out.robot_id = static_cast<uint32_t>(id >> 32);
  out.index = static_cast<uint32_t>(id);
  out.T_world_patch.orientation.w = 1;
  return encode_patch(map.blocks(), config, out).has_value();
}

}  // namespace scancrew::tsdf_mapper::testing
