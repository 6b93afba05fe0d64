// The tsdf_mapper component on the sim backend (ground-truth depth, sim time): single,
// centralized and distributed modes; fusing patches equals integrating every frame into
// one map; a lost patch is recovered by request; a corrupt one is refused, then recovered;
// a lost teammate (kLost on its robot_state) is no holder: the nearest live one replies.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "core/tsdf/patch_codec.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "tests/components/constant_driver.hpp"

namespace scancrew::tsdf_mapper {

using tsdf::Block;
using tsdf::BlockIndex;
using tsdf::kBlockVoxels;
using tsdf::make_patch_id;
using tsdf::state_of;
using tsdf::Voxel;
using tsdf::VoxelState;
namespace {

// Relays a robot's patches from `in` to `out`; robot 1's n-th patch (from 0) is dropped or
// corrupted (a lossy or noisy link).
class PatchLink final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: relays patches, spoiling one";
  struct Config {
    int drop_nth = -1, corrupt_nth = -1;
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional("drop_nth", c.drop_nth);
    p.optional("corrupt_nth", c.corrupt_nth);
    return c;
  }
  PatchLink(ComponentContext c, Config config) : Component(std::move(c)), config_(config) {}
  int relayed = 0, spoiled = 0;

 private:
  Result<void, std::string> on_configure() override {
    out_ = create_publisher<msg::TsdfPatch>("out", {.pool_size = 4});
    create_subscription<msg::TsdfPatch>("in", {.depth = 8}, [this](Sample<msg::TsdfPatch>&& s) {
      const bool spoil = robot_id() == 1;
      const int nth = seen_++;
      if (spoil && nth == config_.drop_nth) {
        ++spoiled;
        return;
      }
      auto loan = out_.loan();
      if (!loan) return;
      **loan = *s;
      if (spoil && nth == config_.corrupt_nth && !(*loan)->data.empty()) {
        (*loan)->data[(*loan)->data.size() / 2] ^= 0x5a;
        ++spoiled;
      }
      ++relayed;
      (void)out_.forward(std::move(*loan));
    });
    return {};
  }
  Config config_;
  int seen_ = 0;
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

// A patch `id` (robot id << 32 | index) holding one observed voxel in block (0, 0, block_z),
// encoded as a mapper with 0.1 m voxels sends it; false if it does not encode.
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

// Robot 2's mapper alone (a robot process), its teammates scripted: robot 3 sends patches
// P0, P1, P2 (robot 4's, which plays no other part) so robot 2 holds them, and lists them; robot 1
// (at x = 10) asks for P0 at 1 s, P1 at 2 s, and P2 and P0 again at 3 s; robot 3 (at x = 9) is
// nearer to it than robot 2 (at the origin); it is lost at 1.5 s and back at 2.5 s. Robot 2's
// replies are logged.
class HolderScript final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: robots 1 and 3 around robot 2's mapper";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  HolderScript(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}
  static uint64_t patch(uint32_t k) { return make_patch_id(4, k); }
  std::vector<std::pair<uint32_t, double>> replies;  // robot 2's: (k of Pk, sim seconds)

 private:
  Result<void, std::string> on_configure() override {
    pose1_ = create_publisher<msg::Odometry>("/r1/pose_gt");
    pose3_ = create_publisher<msg::Odometry>("/r3/pose_gt");
    patch3_ = create_publisher<msg::TsdfPatch>("/r3/patch");
    list3_ = create_publisher<msg::PatchList>("/r3/patch_list");
    state3_ = create_publisher<msg::RobotState>("/r3/robot_state");
    request1_ = create_publisher<msg::PatchRequest>("/r1/patch_request");
    create_subscription<msg::TsdfPatch>(
        "/r2/patch_reply", {.depth = 8}, [this](Sample<msg::TsdfPatch>&& s) {
          replies.emplace_back(s->index, static_cast<double>(clock().now_ns()) * 1e-9);
        });
    create_timer(std::chrono::milliseconds(100), [this] { tick(); });
    return {};
  }
  void pose(Publisher<msg::Odometry>& pub, double x) {
    if (auto loan = pub.loan()) {
      **loan = msg::Odometry{};
      (*loan)->T_world_body.position.x = x;
      (*loan)->tracking_quality = 1;
      (void)pub.publish(std::move(*loan));
    }
  }
  void state(msg::RobotState::Mode mode) {
    if (auto loan = state3_.loan()) {
      **loan = msg::RobotState{};
      (*loan)->header.robot_id = 3;
      (*loan)->mode = mode;
      (void)state3_.publish(std::move(*loan));
    }
  }
  void tick() {
    const int step = ticks_++;  // at (step + 1) · 0.1 s
    if (step == 0) {
      pose(pose1_, 10.0);
      pose(pose3_, 9.0);
      state(msg::RobotState::Mode::kMoving);
    } else if (step == 1) {
      for (uint32_t k = 0; k < 3; ++k)
        if (auto loan = patch3_.loan(); loan && one_voxel_patch(patch(k), 0, **loan))
          (void)patch3_.publish(std::move(*loan));
    } else if (step == 2) {
      if (auto loan = list3_.loan()) {
        (*loan)->patch_ids = {patch(0), patch(1), patch(2)};
        (void)list3_.publish(std::move(*loan));
      }
    } else if (step == 14) {
      state(msg::RobotState::Mode::kLost);
    } else if (step == 24) {
      state(msg::RobotState::Mode::kMoving);
    } else if (step == 9 || step == 19 || step == 29) {
      if (auto loan = request1_.loan()) {
        (*loan)->from_robot = 1;
        (*loan)->patch_ids = step == 9    ? std::vector<uint64_t>{patch(0)}
                             : step == 19 ? std::vector<uint64_t>{patch(1)}
                                          : std::vector<uint64_t>{patch(2), patch(0)};
        (void)request1_.publish(std::move(*loan));
      }
    }
  }
  int ticks_ = 0;
  Publisher<msg::Odometry> pose1_, pose3_;
  Publisher<msg::TsdfPatch> patch3_;
  Publisher<msg::PatchList> list3_;
  Publisher<msg::RobotState> state3_;
  Publisher<msg::PatchRequest> request1_;
};
SCANCREW_REGISTER_COMPONENT(HolderScript, "test_patch_holder_script")

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

// Robot 2's mapper alone, just restarted: robot 3 lists its own patch and one that robot 2's
// old process made (robot 2's id), and answers requests. The restarted mapper asks for both
// and takes both: nothing its old process made is lost to it.
class RestartScript final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: robot 3 around a restarted robot 2";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  RestartScript(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}
  static std::vector<uint64_t> listed() { return {make_patch_id(2, 100), make_patch_id(3, 0)}; }

 private:
  Result<void, std::string> on_configure() override {
    pose3_ = create_publisher<msg::Odometry>("/r3/pose_gt");
    list3_ = create_publisher<msg::PatchList>("/r3/patch_list");
    reply3_ = create_publisher<msg::TsdfPatch>("/r3/patch_reply", {.pool_size = 4});
    create_subscription<msg::PatchRequest>(
        "/r2/patch_request", {.depth = 8},
        [this](Sample<msg::PatchRequest>&& s) { reply(s->patch_ids); });
    create_timer(std::chrono::milliseconds(100), [this] { tick(); });
    return {};
  }
  void reply(const std::vector<uint64_t>& ids) {
    for (const uint64_t id : ids) {
      if (auto loan = reply3_.loan();
          loan && one_voxel_patch(id, static_cast<int>(id >> 32), **loan))
        (void)reply3_.publish(std::move(*loan));
    }
  }
  void tick() {
    if (ticks_++ != 0) return;
    if (auto loan = pose3_.loan()) {
      **loan = msg::Odometry{};
      (*loan)->T_world_body.position.x = 1.0;
      (*loan)->tracking_quality = 1;
      (void)pose3_.publish(std::move(*loan));
    }
    if (auto loan = list3_.loan()) {
      (*loan)->patch_ids = listed();
      (void)list3_.publish(std::move(*loan));
    }
  }
  int ticks_ = 0;
  Publisher<msg::Odometry> pose3_;
  Publisher<msg::PatchList> list3_;
  Publisher<msg::TsdfPatch> reply3_;
};
SCANCREW_REGISTER_COMPONENT(RestartScript, "test_patch_restart_script")

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
