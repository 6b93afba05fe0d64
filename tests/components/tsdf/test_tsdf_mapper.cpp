// The tsdf_mapper component on the sim backend (ground-truth depth, sim time): single,
// centralized and distributed modes; fusing patches equals integrating every frame into
// one map; a lost patch is recovered by request; a corrupt one is refused, then recovered.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "components/tsdf/tsdf_mapper.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "tests/components/constant_driver.hpp"

namespace scancrew::tsdf {
namespace {

// Relays a robot's patches from `in` to `out`; robot 1's patch with the chosen index is
// dropped or corrupted (a lossy or noisy link).
class PatchLink final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: relays patches, spoiling one";
  struct Config {
    int drop_index = -1, corrupt_index = -1;
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional("drop_index", c.drop_index);
    p.optional("corrupt_index", c.corrupt_index);
    return c;
  }
  PatchLink(ComponentContext c, Config config) : Component(std::move(c)), config_(config) {}
  int relayed = 0, spoiled = 0;

 private:
  Result<void, std::string> on_configure() override {
    out_ = create_publisher<msg::TsdfPatch>("out", {.pool_size = 4});
    create_subscription<msg::TsdfPatch>("in", {.depth = 8}, [this](Sample<msg::TsdfPatch>&& s) {
      const bool spoil = robot_id() == 1;
      const auto index = static_cast<int>(s->index);
      if (spoil && index == config_.drop_index) {
        ++spoiled;
        return;
      }
      auto loan = out_.loan();
      if (!loan) return;
      **loan = *s;
      if (spoil && index == config_.corrupt_index && !(*loan)->data.empty()) {
        (*loan)->data[(*loan)->data.size() / 2] ^= 0x5a;
        ++spoiled;
      }
      ++relayed;
      (void)out_.forward(std::move(*loan));
    });
    return {};
  }
  Config config_;
  Publisher<msg::TsdfPatch> out_;
};
SCANCREW_REGISTER_COMPONENT(PatchLink, "test_patch_link")

// Two ground robots in the test arena, each circling the central obstacle, cameras at
// 5 Hz with exact depth. `mappers` is the components block of the mappers.
constexpr const char* kTwoRobotsBlock = R"(
  - {id: 1, namespace: r1, kind: ground, start: [0.0, -2.2, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [0.0, 2.2, 0, 180]})";

std::string launch_text(double duration_s, const std::string& mappers,
                        const std::string& robots = kTwoRobotsBlock) {
  return R"(
clock: sim
executor: {type: step}
run: {duration_s: )" +
         std::to_string(duration_s) + R"(, sim_step_s: 0.05}
robots:)" +
         robots + R"(
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

struct MapDiff {
  size_t compared = 0, state_differs = 0, missing = 0;
  double max_distance = 0, max_weight_rel = 0;
};

// Every observed voxel of a against b.
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

constexpr const char* kMapParams = "voxel_m: 0.1, truncation_m: 0.3, max_weight: 100000";

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

const std::string kTwoRobots = std::string(R"(
  - name: mapper
    type: tsdf_mapper
    params: {mode: distributed, request_delay_s: 0.5, request_retry_s: 1.0, )") +
                               kMapParams + "}\n";

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

// The two robots with robot 1's patches going through a test_patch_link with these params.
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

TEST(TsdfMapper, ALostPatchIsRecoveredByRequest) {
  // robot 1's patch 2 never arrives: robot 2 sees it in robot 1's list and asks for it
  auto launch = run_with_link("{drop_index: 2}");
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
  auto launch = run_with_link("{corrupt_index: 1}");
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
}  // namespace scancrew::tsdf
