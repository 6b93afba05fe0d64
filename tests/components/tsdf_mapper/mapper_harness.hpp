#pragma once

// The tsdf_mapper tests' harness (test_tsdf_mapper): launches of the sim backend
// (ground-truth depth, sim time) with two ground robots circling the test arena's central
// obstacle and the mappers under test; a map comparison; and the test components: a patch
// link that drops or corrupts one patch ("test_patch_link"), and the scripted teammates of
// a lone robot process ("test_patch_holder_script", "test_patch_restart_script"). The
// components are registered in mapper_harness.cpp, linked once into the test executable.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "core/tsdf/patch_codec.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::tsdf_mapper::testing {

using tsdf::make_patch_id;

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

// Two ground robots in the test arena, each circling the central obstacle, cameras at
// 5 Hz with exact depth. `mappers` is the components block of the mappers.
inline constexpr const char* kTwoRobotsBlock = R"(
  - {id: 1, namespace: r1, kind: ground, start: [0.0, -2.2, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [0.0, 2.2, 0, 180]})";

// The launch file: the simulator, the driver, `robots` and `mappers`, for duration_s.
std::string launch_text(double duration_s, const std::string& mappers,
                        const std::string& robots = kTwoRobotsBlock);

// Runs the launch file `text` to its end (a failure and null if it does not load).
std::unique_ptr<Launch> run(const std::string& text);

// The launch's mappers, in the order of its components.
std::vector<TsdfMapper*> mappers(const Launch& launch);

struct MapDiff {
  size_t compared = 0, state_differs = 0, missing = 0;
  double max_distance = 0, max_weight_rel = 0;
};

// Every observed voxel of a against b.
MapDiff compare(const MapSnapshot& a, const MapSnapshot& b);

inline constexpr const char* kMapParams = "voxel_m: 0.1, truncation_m: 0.3, max_weight: 100000";

// The mappers block of the two-robot runs: a distributed mapper on each robot
// (request_delay_s 0.5, request_retry_s 1.0).
extern const std::string kTwoRobots;

// The two robots with robot 1's patches going through a test_patch_link with these params.
std::unique_ptr<Launch> run_with_link(const std::string& link_params);

// A patch `id` (robot id << 32 | index) holding one observed voxel in block (0, 0, block_z),
// encoded as a mapper with 0.1 m voxels sends it; false if it does not encode.
bool one_voxel_patch(uint64_t id, int block_z, msg::TsdfPatch& out);

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

}  // namespace scancrew::tsdf_mapper::testing
