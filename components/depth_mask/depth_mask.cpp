#include "components/depth_mask/depth_mask.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::depth_mask {

DepthMask::Config DepthMask::read_config(ParamReader& p) {
  Config c;
  p.optional_list("ground_body_m", c.ground_body_m, 3, {0.01, 20})
      .doc("a ground teammate's box: length, width, height (m)");
  p.optional_list("multirotor_body_m", c.multirotor_body_m, 3, {0.01, 20})
      .doc("a multirotor teammate's box: length, width, height (m)");
  p.optional("margin_m", c.margin_m, {0, 5}).doc("grows every box side (m)");
  p.optional("max_pose_age_s", c.max_pose_age_s, {0.001, 3600})
      .doc("older teammate poses are not used (the mask would lag) (s)");
  return c;
}

DepthMask::DepthMask(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> DepthMask::on_configure() {
  for (const TeamMember& m : team()) {
    if (m.id == robot_id()) continue;
    Teammate t;
    t.ns = m.ns;
    const bool ground = m.kind == robot::RobotKind::kGround;
    const std::vector<double>& size = ground ? config_.ground_body_m : config_.multirotor_body_m;
    for (size_t i = 0; i < 3; ++i) t.half[i] = 0.5 * size[i] + config_.margin_m;
    t.center = {0, 0, ground ? 0.5 * size[2] : 0};
    teammates_.push_back(t);
  }
  for (size_t i = 0; i < teammates_.size(); ++i)
    create_teammate_subscription<msg::Odometry>("pose", teammates_[i].ns, {.depth = 4},
                                                [this, i](Sample<msg::Odometry>&& pose) {
                                                  if (pose->tracking_quality <= 0)
                                                    return;  // a lost teammate keeps its last pose
                                                  teammates_[i].T_world_body = pose->T_world_body;
                                                  teammates_[i].stamp_ns = pose->header.stamp_ns;
                                                });
  out_ = create_publisher<msg::DepthImage>("depth_masked");
  create_subscription<msg::DepthImage>(
      "depth", {.depth = 4}, [this](Sample<msg::DepthImage>&& d) { on_depth(std::move(d)); });
  return {};
}

void DepthMask::on_depth(Sample<msg::DepthImage>&& depth) {
  ++frames_;
  // the pixels are indexed by the intrinsics: an image whose depth_m is not width x height
  // (a recording's, a DDS import's) would be read and written past its end. Dropped, as the
  // mapper drops it; a camera that cannot project is dropped too.
  const msg::CameraIntrinsics& in = depth->intrinsics;
  const char* problem = nullptr;
  if (depth->depth_m.size() != size_t{in.width} * in.height)
    problem = "depth_m does not hold width x height pixels";
  else if (!(std::isfinite(in.fx) && std::isfinite(in.fy) && std::isfinite(in.cx) &&
             std::isfinite(in.cy) && in.fx > 0 && in.fy > 0))
    problem = "intrinsics not finite or focal lengths not positive";
  if (problem != nullptr) {
    if (refused_++ == 0)
      SCANCREW_LOG_WARN(
          "%s: depth image at t = %.3f s dropped: %s (%zu values, %u x %u; further "
          "ones are counted)",
          qualified_name().c_str(), static_cast<double>(depth->header.stamp_ns) * 1e-9, problem,
          depth->depth_m.size(), in.width, in.height);
    return;
  }
  auto loan = out_.loan();
  if (!loan) return;  // counted by the topic
  msg::DepthImage& out = **loan;
  out = *depth;  // copies into the slot's kept capacity
  const auto max_age = static_cast<int64_t>(config_.max_pose_age_s * 1e9);
  // every teammate's box in the camera frame: p_box = T_box_cam · p_cam
  std::vector<std::pair<Eigen::Isometry3d, const Teammate*>> boxes;
  const Eigen::Isometry3d T_world_cam = msg::to_eigen(out.T_world_cam);
  for (const Teammate& t : teammates_) {
    if (t.stamp_ns == msg::kStampUnset || std::abs(out.header.stamp_ns - t.stamp_ns) > max_age)
      continue;
    Eigen::Isometry3d T_world_box = msg::to_eigen(t.T_world_body);
    T_world_box.translate(Eigen::Vector3d(t.center[0], t.center[1], t.center[2]));
    boxes.emplace_back(T_world_box.inverse() * T_world_cam, &t);
  }
  if (!boxes.empty()) {
    const msg::CameraIntrinsics& k = out.intrinsics;
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    for (uint32_t v = 0; v < k.height; ++v)
      for (uint32_t u = 0; u < k.width; ++u) {
        float& z = out.depth_m[size_t{v} * k.width + u];
        if (!std::isfinite(z)) continue;
        const Eigen::Vector3d p_cam(z * (u - k.cx) / k.fx, z * (v - k.cy) / k.fy, z);
        for (const auto& [T_box_cam, t] : boxes) {
          const Eigen::Vector3d p = T_box_cam * p_cam;
          if (std::abs(p.x()) <= t->half[0] && std::abs(p.y()) <= t->half[1] &&
              std::abs(p.z()) <= t->half[2]) {
            z = kNaN;
            ++masked_;
            break;
          }
        }
      }
  }
  (void)out_.forward(std::move(*loan));  // the input's header: same robot, stamp and sequence
}

SCANCREW_REGISTER_COMPONENT(DepthMask, "depth_mask")

}  // namespace scancrew::depth_mask
