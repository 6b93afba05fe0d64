#include "components/stereo_depth/stereo_depth.hpp"

#include <algorithm>
#include <cmath>

#include "components/stereo_depth/stereo_matcher.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::stereo_depth {

StereoDepth::Config StereoDepth::read_config(ParamReader& p) {
  Config c;
  SgbmParams& s = c.sgbm;
  p.optional("num_disparities", s.num_disparities, {0, 1024})
      .doc("SGBM disparity search range (multiple of 16; 0: f·B/min_range_m)");
  if (s.num_disparities % 16 != 0)
    p.report("num_disparities", "must be a multiple of 16 (or 0: from the camera's min range)");
  p.optional("block_size", s.block_size, {1, 11}).doc("SGBM block size (odd, px)");
  if (s.block_size % 2 == 0) p.report("block_size", "must be odd");
  p.optional("p1", s.p1, {0, 100000}).doc("SGBM smoothness penalty P1 (0: 8·block²)");
  p.optional("p2", s.p2, {0, 400000}).doc("SGBM smoothness penalty P2 (0: 32·block²; > p1)");
  if (s.p1 != 0 && s.p2 != 0 && s.p2 <= s.p1) p.report("p2", "must be greater than p1");
  p.optional("uniqueness_ratio", s.uniqueness_ratio, {0, 100})
      .doc("% margin of the best cost over the second best");
  p.optional("speckle_window_size", s.speckle_window_size, {0, 10000})
      .doc("speckle filter window (px; 0: off)");
  p.optional("speckle_range", s.speckle_range, {0, 64})
      .doc("disparity variation inside a speckle (px)");
  p.optional("disp12_max_diff", s.disp12_max_diff, {-1, 64}).doc("left-right check (px; < 0: off)");
  p.optional("pre_filter_cap", s.pre_filter_cap, {1, 63}).doc("OpenCV SGBM preFilterCap");
  p.choice("mode", s.mode, kSgbmModeNames).doc("SGBM paths: sgbm (5), hh (8) or sgbm_3way");
  p.optional("texture_threshold", s.texture_threshold, {0, 1000})
      .doc("a pixel whose window's mean |Sobel x| is below this (grey levels) is NaN (0: off)");
  p.optional("texture_window", s.texture_window, {3, 31}).doc("texture check window (odd, px)");
  if (s.texture_window % 2 == 0) p.report("texture_window", "must be odd");
  p.optional("min_range_m", c.min_range_m, {0.01, 100})
      .doc("nearest depth published (m; table 5.3)");
  p.optional("max_range_m", c.max_range_m, {0.02, 1000})
      .doc("farthest depth published (m; table 5.3)");
  if (c.max_range_m <= c.min_range_m) p.report("max_range_m", "must be greater than min_range_m");
  p.optional("max_pending_frames", c.max_pending_frames, {1, 1000})
      .doc("frames waiting for their pose");
  p.optional("pose_history", c.pose_history, {1, 100000})
      .doc("poses kept for frames still to come");
  NearFieldFillConfig& n = c.near_field;
  p.optional("near_field_range_m", n.range_m, {0, 10})
      .doc(
          "ground robots: invalid depth where the floor ends nearer than this is filled as an "
          "obstacle (m; 0: off)");
  p.optional("near_field_confirm_factor", n.confirm_factor, {1.01, 10})
      .doc("the invalid run must reach rays meeting the floor this much farther");
  p.optional("near_field_floor_tolerance_m", n.floor_tolerance_m, {0.001, 1})
      .doc("a valid point this near the floor plane is floor (m)");
  p.optional("near_field_max_height_m", n.max_height_m, {0.01, 10})
      .doc("filled up to this height above the floor (m)");
  return c;
}

StereoDepth::StereoDepth(ComponentContext context, Config config)
    : Component(std::move(context)), config_(config) {}

StereoDepth::~StereoDepth() = default;

Result<void, std::string> StereoDepth::on_configure() {
  if (std::string problem = config_.near_field.validate(); !problem.empty())
    return make_unexpected(problem);
  // the fill needs a floor under the camera: ground robots only
  const auto self = std::find_if(team().begin(), team().end(),
                                 [&](const TeamMember& m) { return m.id == robot_id(); });
  fill_near_field_ = config_.near_field.range_m > 0 && self != team().end() &&
                     self->kind == robot::RobotKind::kGround;
  matcher_ =
      std::make_unique<StereoMatcher>(config_.sgbm, config_.min_range_m, config_.max_range_m);
  depth_ = create_publisher<msg::DepthImage>("depth");
  create_subscription<msg::StereoFrame>(
      "stereo", {.depth = config_.max_pending_frames},
      [this](Sample<msg::StereoFrame>&& f) { on_frame(std::move(f)); });
  create_subscription<msg::Odometry>("pose", {.depth = 16},
                                     [this](Sample<msg::Odometry>&& p) { on_pose(std::move(p)); });
  return {};
}

bool StereoDepth::valid(const msg::StereoFrame& f) {
  const size_t n = size_t{f.intrinsics.width} * f.intrinsics.height;
  const auto once = [&](uint64_t& counter, const char* what) {
    if (counter++ == 0)
      SCANCREW_LOG_WARN("%s: frame %llu skipped: %s (further ones are counted)",
                        qualified_name().c_str(), static_cast<unsigned long long>(f.header.seq),
                        what);
    return false;
  };
  if (f.left.empty() || f.right.empty()) return once(stats_.empty, "empty image");
  if (f.left.size() != f.right.size()) return once(stats_.size_mismatch, "left/right sizes differ");
  // finite too: an infinite focal length made the automatic disparity count infinite
  if (n != f.left.size() || !(f.intrinsics.fx > 0) || !(f.baseline_m > 0) ||
      !std::isfinite(f.intrinsics.fx) || !std::isfinite(f.baseline_m))
    return once(stats_.intrinsics_mismatch,
                "the camera model does not match the image (size, focal length or baseline)");
  return true;
}

void StereoDepth::on_frame(Sample<msg::StereoFrame>&& frame) {
  ++stats_.frames;
  if (!valid(*frame)) return;
  if (pending_.size() >= config_.max_pending_frames) {
    if (stats_.no_pose++ == 0)
      SCANCREW_LOG_WARN("%s: no pose for frame stamped %lld ns: dropped (is '%s' published?)",
                        qualified_name().c_str(),
                        static_cast<long long>(pending_.front()->header.stamp_ns),
                        resolve("pose").c_str());
    pending_.pop_front();
  }
  pending_.push_back(std::move(frame));
  process_ready();
}

void StereoDepth::on_pose(Sample<msg::Odometry>&& pose) {
  if (poses_.size() >= config_.pose_history) poses_.pop_front();
  poses_.push_back(std::move(pose));
  process_ready();
}

void StereoDepth::process_ready() {
  while (!pending_.empty()) {
    const int64_t stamp = pending_.front()->header.stamp_ns;
    const msg::Odometry* match = nullptr;
    bool newer = false;
    for (const auto& p : poses_) {
      if (p->header.stamp_ns == stamp) match = p.get();
      newer = newer || p->header.stamp_ns > stamp;
    }
    if (match == nullptr) {
      if (!newer) return;  // its pose may still come
      // poses arrive in stamp order: a newer one means this frame's pose will not come
      if (stats_.no_pose++ == 0)
        SCANCREW_LOG_WARN("%s: no pose stamped %lld ns: frame dropped (further ones are counted)",
                          qualified_name().c_str(), static_cast<long long>(stamp));
    } else if (match->tracking_quality <= 0) {
      ++stats_.pose_lost;  // tracking lost: the frame cannot be placed in the map
    } else {
      compute(*pending_.front(), *match);
    }
    pending_.pop_front();
    while (!poses_.empty() && poses_.front()->header.stamp_ns <= stamp) poses_.pop_front();
  }
}

void StereoDepth::compute(const msg::StereoFrame& f, const msg::Odometry& pose) {
  auto loan = depth_.loan();
  if (!loan) return;  // counted by the topic as a loan failure
  msg::DepthImage& d = **loan;
  d.header.stamp_ns = f.header.stamp_ns;
  d.intrinsics = f.intrinsics;
  d.min_range_m = config_.min_range_m;
  d.max_range_m = config_.max_range_m;
  d.T_world_cam = msg::to_msg(msg::to_eigen(pose.T_world_body) * msg::to_eigen(f.T_body_cam));
  matcher_->compute(f.left.data(), f.right.data(), f.intrinsics.width, f.intrinsics.height,
                    f.intrinsics.fx, f.baseline_m, d.depth_m);
  if (fill_near_field_) {
    const double blind_m =
        std::max(config_.min_range_m, f.intrinsics.fx * f.baseline_m /
                                          matcher_->num_disparities(f.intrinsics.fx, f.baseline_m));
    const NearFieldFillStats n = fill_near_field(
        d.depth_m, f.intrinsics, msg::to_eigen(f.T_body_cam), blind_m, config_.near_field);
    stats_.filled_images += n.columns > 0 ? 1 : 0;
    stats_.filled_columns += n.columns;
    stats_.filled_pixels += n.pixels;
  }
  if (depth_.publish(std::move(*loan))) ++stats_.published;
}

void StereoDepth::on_deactivate() {
  SCANCREW_LOG_INFO(
      "%s: %llu frames, %llu depth images; skipped: %llu empty, %llu size mismatch, %llu "
      "camera model mismatch, %llu without pose, %llu with tracking lost; near-field fill: %llu "
      "images, %llu columns, %llu pixels",
      qualified_name().c_str(), static_cast<unsigned long long>(stats_.frames),
      static_cast<unsigned long long>(stats_.published),
      static_cast<unsigned long long>(stats_.empty),
      static_cast<unsigned long long>(stats_.size_mismatch),
      static_cast<unsigned long long>(stats_.intrinsics_mismatch),
      static_cast<unsigned long long>(stats_.no_pose),
      static_cast<unsigned long long>(stats_.pose_lost),
      static_cast<unsigned long long>(stats_.filled_images),
      static_cast<unsigned long long>(stats_.filled_columns),
      static_cast<unsigned long long>(stats_.filled_pixels));
}

SCANCREW_REGISTER_COMPONENT(StereoDepth, "stereo_depth")

}  // namespace scancrew::stereo_depth
