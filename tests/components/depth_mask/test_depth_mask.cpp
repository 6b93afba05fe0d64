// The depth mask blanks a teammate seen by a robot, and nothing else.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>

#include "components/depth_mask/depth_mask.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::perception {
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

}  // namespace
}  // namespace scancrew::perception
