#include "bench/perception/perception_bench.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <vector>

#include "bench/perception/sequence.hpp"
#include "components/recorder/recording.hpp"
#include "components/stereo_depth/depth_error.hpp"
#include "components/stereo_depth/stereo_depth.hpp"
#include "components/stereo_depth/stereo_matcher.hpp"
#include "components/vio/frame_check.hpp"
#include "components/vio/imu_buffer.hpp"
#include "components/vio/stereo_odometry.hpp"
#include "components/vio/vio.hpp"
#include "eval/odometry_error.hpp"
#include "executors/params.hpp"
#include "interfaces/codec.hpp"
#include "interfaces/eigen_conversions.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::bench {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Timing {
  std::vector<double> ms;
  double mean() const {
    double s = 0;
    for (double v : ms) s += v;
    return ms.empty() ? 0 : s / static_cast<double>(ms.size());
  }
  double percentile(double p) const {
    if (ms.empty()) return 0;
    std::vector<double> sorted = ms;
    const auto k = static_cast<size_t>(p * static_cast<double>(sorted.size() - 1));
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
    return sorted[k];
  }
};

// The components' default parameters, read as they would be from an empty params block.
template <class C>
typename C::Config defaults() {
  ParamReader p = ParamReader::from_yaml_string("{}", "defaults");
  return C::read_config(p);
}

vio::Vio::Config vio_defaults(bool no_coast) {
  vio::Vio::Config c = defaults<vio::Vio>();
  if (no_coast) c.odometry.max_coast_s = 0;
  return c;
}

// Plays the recording through the stereo and odometry cores. A frame is processed once the
// IMU is kSettleNs past its stamp: the gyro prior needs the samples up to the frame, and
// by then the ground-truth pose and depth of the same instant (recorded in the same sim
// step, in any topic order) have been read.
constexpr int64_t kSettleNs = 50'000'000;

class Evaluator {
 public:
  Evaluator(std::string robot, bool no_coast, bool vio_only)
      : robot_(std::move(robot)),
        vio_only_(vio_only),
        stereo_config_(defaults<stereo_depth::StereoDepth>()),
        vio_config_(vio_defaults(no_coast)),
        matcher_(stereo_config_.sgbm, stereo_config_.min_range_m, stereo_config_.max_range_m),
        odometry_(vio_config_.odometry),
        imu_(static_cast<int64_t>(vio_config_.imu_max_gap_s * 1e9)) {}

  Result<void, std::string> play(const std::string& path) {
    auto opened = recorder::RecordingReader::open(path);
    if (!opened) return make_unexpected(opened.error());
    recorder::RecordingReader reader = std::move(opened).value();
    msg::StereoFrame stereo;
    msg::Imu imu;
    msg::Odometry pose;
    msg::DepthImage depth;
    for (;;) {
      auto next = reader.next();
      if (!next) return make_unexpected(next.error());
      if (!*next) break;
      const recorder::LogEntry& entry = **next;
      const recorder::LogTopic& topic = reader.topics()[entry.topic];
      if (!robot_.empty() && !topic.name.starts_with("/" + robot_ + "/")) continue;
      const std::string& type = topic.type;
      Result<void, std::string> decoded;
      if (type == msg::StereoFrame::kTypeName) {
        if (stereo_topic_.empty()) stereo_topic_ = topic.name;
        if (topic.name != stereo_topic_)
          return make_unexpected(path + ": stereo on " + stereo_topic_ + " and " + topic.name +
                                 ": several robots; pick one with --robot NS");
        if (decoded = msg::decode(entry.message, stereo); decoded) frames_.push_back(stereo);
      } else if (type == msg::Imu::kTypeName) {
        if (decoded = msg::decode(entry.message, imu); decoded) on_imu(imu);
      } else if (type == msg::Odometry::kTypeName && topic.name.ends_with("pose_gt")) {
        if (decoded = msg::decode(entry.message, pose); decoded)
          truth_[pose.header.stamp_ns] = pose.T_world_body;
      } else if (type == msg::DepthImage::kTypeName) {
        if (decoded = msg::decode(entry.message, depth); decoded)
          depth_gt_[depth.header.stamp_ns] = depth.depth_m;
      }
      if (!decoded) return make_unexpected(path + ": " + decoded.error());
      process_ready(false);
      if (processed_ % 50 == 0 && processed_ != reported_) {
        reported_ = processed_;
        std::fprintf(stderr, "\rprocessing: %llu frames",
                     static_cast<unsigned long long>(processed_));
      }
    }
    process_ready(true);
    std::fprintf(stderr, "\rprocessing: %llu frames\n",
                 static_cast<unsigned long long>(processed_));
    if (processed_ == 0)
      return make_unexpected(path + ": no stereo frames" +
                             (robot_.empty() ? std::string() : " under /" + robot_ + "/"));
    return {};
  }

  nlohmann::json result(double rpe_segment_m) const {
    nlohmann::json out;
    const stereo_depth::DepthError d = depth_error_.result();
    std::vector<eval::StampedPose> truth;
    for (const auto& [stamp, pose] : truth_) truth.push_back({stamp, pose});
    const auto e = eval::odometry_error(estimate_, truth, {.segment_length_m = rpe_segment_m});
    out["frames"] = processed_;
    out["width"] = width_;
    out["height"] = height_;
    out["depth_ms"] = depth_ms_.mean();
    out["depth_ms_p95"] = depth_ms_.percentile(0.95);
    out["vio_ms"] = vio_ms_.mean();
    out["vio_ms_p95"] = vio_ms_.percentile(0.95);
    out["depth_median_rel_err"] = d.median_rel;
    out["depth_median_abs_err_m"] = d.median_abs_m;
    out["depth_valid_ratio"] = d.valid_ratio;
    out["depth_outlier_ratio"] = d.outlier_ratio;
    out["depth_range_m"] = {stereo_config_.min_range_m, stereo_config_.max_range_m};
    out["depth_frames_with_truth"] = depth_frames_;
    out["vio_resets"] = odometry_.resets();
    out["vio_keyframes"] = odometry_.keyframes();
    out["vio_untracked_frames"] = untracked_;
    out["vio_coasted_frames"] = odometry_.coasted_frames();
    if (e) {
      out["distance_m"] = e->distance_m;
      out["losses_per_100m"] = e->distance_m > 0 ? 100.0 * odometry_.resets() / e->distance_m : 0.0;
      out["ate_m"] = e->ate_rmse_m;
      out["ate_max_m"] = e->ate_max_m;
      out["rpe_pct"] = e->rpe_mean_percent;
      out["rpe_max_pct"] = e->rpe_max_percent;
      out["rpe_segment_m"] = rpe_segment_m;
      out["rpe_deg_per_m"] = e->rpe_rotation_deg_per_m;
    } else {
      out["odometry_error"] = e.error();
    }
    return out;
  }

 private:
  void on_imu(const msg::Imu& imu) {
    if (vio::check_imu(imu) != vio::InputError::kNone) return;
    if (imu_.add(imu.header.stamp_ns, msg::to_eigen(imu.linear_acceleration_mps2),
                 msg::to_eigen(imu.angular_velocity_radps)))
      last_imu_ns_ = imu.header.stamp_ns;
  }

  void process_ready(bool at_end) {
    while (!frames_.empty() &&
           (at_end || last_imu_ns_ > frames_.front().header.stamp_ns + kSettleNs)) {
      process(frames_.front());
      frames_.pop_front();
    }
  }

  void process(const msg::StereoFrame& f) {
    if (vio::check_stereo(f) != vio::InputError::kNone) return;
    width_ = f.intrinsics.width;
    height_ = f.intrinsics.height;
    if (!vio_only_) compute_depth(f);
    vio(f);
    ++processed_;
  }

  void compute_depth(const msg::StereoFrame& f) {
    const int64_t stamp = f.header.stamp_ns;
    const uint32_t w = f.intrinsics.width, h = f.intrinsics.height;
    const auto t0 = Clock::now();
    matcher_.compute(f.left.data(), f.right.data(), w, h, f.intrinsics.fx, f.baseline_m, depth_);
    depth_ms_.ms.push_back(ms_since(t0));
    if (auto gt = depth_gt_.find(stamp); gt != depth_gt_.end()) {
      depth_error_.add(depth_, gt->second, stereo_config_.min_range_m, stereo_config_.max_range_m);
      ++depth_frames_;
      depth_gt_.erase(depth_gt_.begin(), std::next(gt));
    }
  }

  void vio(const msg::StereoFrame& f) {
    const int64_t stamp = f.header.stamp_ns;
    const uint32_t w = f.intrinsics.width, h = f.intrinsics.height;
    if (!odometry_.started()) {
      const auto start = truth_.find(stamp);
      if (start == truth_.end()) return;  // the ground truth gives the start pose
      odometry_.set_start(msg::to_eigen(start->second));
    }
    vio::ImuInterval interval;
    if (last_frame_ns_ != 0) {
      interval.q_prevbody_body = imu_.rotation(last_frame_ns_, stamp);
      interval.mean_specific_force_mps2 = imu_.mean_accel(stamp, stamp - last_frame_ns_);
    }
    last_frame_ns_ = stamp;
    imu_.drop_before(stamp);
    vio::StereoInput input;
    input.left = {f.left.data(), static_cast<int>(w), static_cast<int>(h)};
    input.right = {f.right.data(), static_cast<int>(w), static_cast<int>(h)};
    input.intrinsics = f.intrinsics;
    input.baseline_m = f.baseline_m;
    input.T_body_cam = msg::to_eigen(f.T_body_cam);
    input.stamp_ns = stamp;
    const auto t0 = Clock::now();
    const vio::TrackingResult r = odometry_.process(input, interval);
    vio_ms_.ms.push_back(ms_since(t0));
    if (r.quality > 0)
      estimate_.push_back({stamp, msg::to_msg(r.T_world_body)});
    else
      ++untracked_;
  }

  std::string robot_, stereo_topic_;
  bool vio_only_ = false;
  stereo_depth::StereoDepth::Config stereo_config_;
  vio::Vio::Config vio_config_;
  stereo_depth::StereoMatcher matcher_;
  vio::StereoOdometry odometry_;
  vio::ImuBuffer imu_;
  std::deque<msg::StereoFrame> frames_;
  std::map<int64_t, msg::Pose3> truth_;
  std::map<int64_t, std::vector<float>> depth_gt_;
  std::vector<float> depth_;
  std::vector<eval::StampedPose> estimate_;
  stereo_depth::DepthErrorAccumulator depth_error_;
  Timing depth_ms_, vio_ms_;
  int64_t last_imu_ns_ = 0, last_frame_ns_ = 0;
  uint64_t processed_ = 0, reported_ = 0, depth_frames_ = 0, untracked_ = 0;
  uint32_t width_ = 0, height_ = 0;
};

}  // namespace

int run_perception_bench(const PerceptionBenchOptions& o) {
  std::string path = o.recording;
  nlohmann::json sequence;
  std::filesystem::path temp_dir;
  if (path.empty()) {
    if (o.keep.empty()) {
      temp_dir = std::filesystem::temp_directory_path() /
                 ("scancrew_bench_perception_" + std::to_string(::getpid()));
      std::filesystem::create_directories(temp_dir);
      path = (temp_dir / "parking_lot.mcap").string();
    } else {
      path = o.keep;
    }
    const auto t0 = Clock::now();
    auto recorded = record_sequence({.scene_path = o.scene_path,
                                     .out_path = path,
                                     .distance_m = o.distance_m,
                                     .width = o.width,
                                     .height = o.height,
                                     .seed = o.seed});
    if (!recorded) {
      std::fprintf(stderr, "bench perception: recording failed: %s\n", recorded.error().c_str());
      if (!temp_dir.empty()) std::filesystem::remove_all(temp_dir);
      return 1;
    }
    sequence = {{"driven_m", recorded->driven_m},
                {"sim_s", recorded->sim_s},
                {"messages", recorded->messages},
                {"record_wall_s", ms_since(t0) * 1e-3}};
  }
  std::error_code ec;
  sequence["path"] = o.keep.empty() && o.recording.empty() ? "(temporary)" : path;
  sequence["bytes"] = std::filesystem::file_size(path, ec);

  cv::setNumThreads(1);  // the targets are per frame on one core
  Evaluator evaluator(o.robot, o.no_coast, o.vio_only);
  const auto played = evaluator.play(path);
  if (!temp_dir.empty()) std::filesystem::remove_all(temp_dir);
  if (!played) {
    std::fprintf(stderr, "bench perception: %s\n", played.error().c_str());
    return 1;
  }
  nlohmann::json out = evaluator.result(o.rpe_segment_m);
  out["sequence"] = sequence;
  if (o.json) {
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("perception on %llu frames %ux%u, one OpenCV thread\n",
                static_cast<unsigned long long>(out["frames"].get<uint64_t>()), o.width, o.height);
    std::printf(
        "  stereo depth: %.2f ms/frame (p95 %.2f); median rel. error %.2f %% (abs %.3f m), "
        "valid %.1f %%, outliers %.1f %%\n",
        out["depth_ms"].get<double>(), out["depth_ms_p95"].get<double>(),
        100 * out["depth_median_rel_err"].get<double>(),
        out["depth_median_abs_err_m"].get<double>(), 100 * out["depth_valid_ratio"].get<double>(),
        100 * out["depth_outlier_ratio"].get<double>());
    std::printf("  vio: %.2f ms/frame (p95 %.2f), %llu keyframes\n", out["vio_ms"].get<double>(),
                out["vio_ms_p95"].get<double>(),
                static_cast<unsigned long long>(out["vio_keyframes"].get<uint64_t>()));
    if (!out.contains("ate_m"))
      std::printf("  odometry error: %s\n", out["odometry_error"].get<std::string>().c_str());
    if (out.contains("ate_m"))
      std::printf(
          "  odometry over %.1f m: ATE %.3f m (max %.3f), RPE over %.0f m %.2f %% (max %.2f "
          "%%), %u resets (%.2f per 100 m), %llu frames coasted\n",
          out["distance_m"].get<double>(), out["ate_m"].get<double>(),
          out["ate_max_m"].get<double>(), o.rpe_segment_m, out["rpe_pct"].get<double>(),
          out["rpe_max_pct"].get<double>(), out["vio_resets"].get<uint32_t>(),
          out["losses_per_100m"].get<double>(),
          static_cast<unsigned long long>(out["vio_coasted_frames"].get<uint64_t>()));
  }
  return out.contains("ate_m") ? 0 : 1;
}

}  // namespace scancrew::bench
