// The depth mask blanks a teammate seen by a robot, and nothing else.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>

#include "components/depth_mask/depth_mask.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::depth_mask {
namespace {

class MaskPairs final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: pairs depth and depth_masked";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  MaskPairs(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  std::map<int64_t, msg::DepthImage> in, out;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::DepthImage>(
        "depth", {.depth = 4},
        [this](Sample<msg::DepthImage>&& s) { in[s->header.stamp_ns] = *s; });
    create_subscription<msg::DepthImage>(
        "depth_masked", {.depth = 4},
        [this](Sample<msg::DepthImage>&& s) { out[s->header.stamp_ns] = *s; });
    return {};
  }
};
SCANCREW_REGISTER_COMPONENT(MaskPairs, "test_mask_pairs")

Eigen::Vector3d world_point(const msg::DepthImage& d, uint32_t u, uint32_t v) {
  const double z = d.depth_m[size_t{v} * d.intrinsics.width + u];
  const msg::CameraIntrinsics& k = d.intrinsics;
  return msg::to_eigen(d.T_world_cam) *
         Eigen::Vector3d(z * (u - k.cx) / k.fx, z * (v - k.cy) / k.fy, z);
}

TEST(DepthMask, BlanksTheTeammateAndNothingElse) {
  // r1 looks along +x at r2, 2 m ahead and turned 90 degrees
  auto launch = Launch::from_string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 0.5, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: ground, start: [-3.0, -2.5, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [-1.0, -2.5, 0, 90]}
remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params:
      scene: )" SCANCREW_SOURCE_DIR R"(/launch_cfg/scenes/test_arena.yaml
      depth_noise: false
  - {name: mask, type: depth_mask, params: {margin_m: 0.1}}
  - {name: pairs, type: test_mask_pairs}
)",
                                    "mask.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  MaskPairs* r1 = nullptr;
  for (const auto& c : (*launch)->components())
    if (auto* p = dynamic_cast<MaskPairs*>(c.get()); p && c->qualified_name() == "/r1/pairs")
      r1 = p;
  ASSERT_NE(r1, nullptr);
  ASSERT_FALSE(r1->out.empty());
  const msg::DepthImage& in = r1->in.begin()->second;
  const msg::DepthImage& out = r1->out.at(r1->in.begin()->first);
  ASSERT_EQ(in.depth_m.size(), out.depth_m.size());
  size_t masked = 0;
  for (uint32_t v = 0; v < in.intrinsics.height; ++v)
    for (uint32_t u = 0; u < in.intrinsics.width; ++u) {
      const size_t i = size_t{v} * in.intrinsics.width + u;
      if (!std::isfinite(in.depth_m[i])) continue;
      const Eigen::Vector3d p = world_point(in, u, v);
      // r2's body in the simulator: 0.40 along x (turned), 0.44 along y, z 0.02..0.22
      const bool on_r2 =
          std::abs(p.x() + 1.0) <= 0.21 && std::abs(p.y() + 2.5) <= 0.23 && p.z() <= 0.23;
      // the mask's box: 0.44 x 0.40 x 0.40 grown by 0.1 m, turned with r2
      const bool in_box = std::abs(p.x() + 1.0) <= 0.30 + 1e-6 &&
                          std::abs(p.y() + 2.5) <= 0.32 + 1e-6 && p.z() <= 0.50 + 1e-6;
      if (std::isnan(out.depth_m[i])) {
        ++masked;
        EXPECT_TRUE(in_box) << "blanked a pixel off the teammate: " << p.transpose();
      } else {
        EXPECT_FALSE(on_r2) << "kept a pixel on the teammate: " << p.transpose();
        EXPECT_EQ(out.depth_m[i], in.depth_m[i]);
      }
    }
  EXPECT_GT(masked, 200u);
  // the header passes through: same stamp and robot
  EXPECT_EQ(out.header.stamp_ns, in.header.stamp_ns);
  EXPECT_EQ(out.header.robot_id, 1u);
}

// Publishes each robot's pose and a depth image whose depth_m is shorter than its
// intrinsics say (a recording's or a DDS import's), every 50 ms of sim time.
class ShortDepth final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: poses and short depth images";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  ShortDepth(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

 private:
  Result<void, std::string> on_configure() override {
    pose_ = create_publisher<msg::Odometry>("pose_gt", {.pool_size = 2});
    depth_ = create_publisher<msg::DepthImage>("depth", {.pool_size = 2});
    create_timer(std::chrono::milliseconds(50), [this] {
      const int64_t now = clock().now_ns();
      if (auto pose = pose_.loan()) {
        **pose = msg::Odometry{};
        (*pose)->header.stamp_ns = now;
        (*pose)->T_world_body.position = {2.0 * robot_id(), 0, 0};
        (void)pose_.publish(std::move(*pose));
      }
      if (auto depth = depth_.loan()) {
        msg::DepthImage& d = **depth;
        d = msg::DepthImage{};
        d.header.stamp_ns = now;
        d.intrinsics = {.width = 640, .height = 480, .fx = 300, .fy = 300, .cx = 320, .cy = 240};
        d.T_world_cam.position = {2.0 * robot_id(), 0, 0};
        d.depth_m.assign(10, 2.0F);  // not 640 x 480
        (void)depth_.publish(std::move(*depth));
      }
    });
    return {};
  }
  Publisher<msg::Odometry> pose_;
  Publisher<msg::DepthImage> depth_;
};
SCANCREW_REGISTER_COMPONENT(ShortDepth, "test_short_depth")

// Step 12's review: the mask indexed depth_m by the intrinsics and wrote past its end (a
// segfault) when a teammate's pose was fresh. It drops such an image and counts it.
TEST(DepthMask, DropsAnImageWhosePixelsDoNotMatchItsIntrinsics) {
  auto launch = Launch::from_string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 0.5, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: ground, start: [0, 0, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [2, 0, 0, 0]}
remap: {pose: pose_gt}
components:
  - {name: feed, type: test_short_depth}
  - {name: mask, type: depth_mask, params: {margin_m: 0.1}}
  - {name: pairs, type: test_mask_pairs}
)",
                                    "short.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  size_t masks = 0;
  for (const auto& c : (*launch)->components()) {
    if (auto* m = dynamic_cast<DepthMask*>(c.get())) {
      ++masks;
      EXPECT_GT(m->frames(), 3U);
      EXPECT_EQ(m->refused_frames(), m->frames());
      EXPECT_EQ(m->masked_pixels(), 0U);
    }
    if (auto* p = dynamic_cast<MaskPairs*>(c.get())) {
      EXPECT_FALSE(p->in.empty());
      EXPECT_TRUE(p->out.empty()) << "a refused image was passed on";
    }
  }
  EXPECT_EQ(masks, 2U);
}

}  // namespace
}  // namespace scancrew::depth_mask
