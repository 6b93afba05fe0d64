#pragma once

// The two components of `scancrew bench pipeline` (bench/pipeline/pipeline_bench.hpp), both
// registered for the bench's launch files only:
//
//   bench_frame_capture   keeps a robot's stereo pairs and their ground-truth poses (same
//                         stamp) in memory while the team simulator renders them (lockstep),
//                         so the bench can publish them later at any camera rate;
//   bench_pipeline_probe  records the capture stamp and the publisher's monotonic publish
//                         time of every depth image, map snapshot, viewpoint-cluster set and
//                         plan of one robot's graph. The stamps chain a plan back to the
//                         stereo pair it follows: each stage keeps its input's capture stamp
//                         (stereo_depth, tsdf_mapper's snapshots, ise_extractor,
//                         high_level_planner).
//
// No thesis equations: measurement only. Thread safety: the recorded vectors are written
// by the executor's callbacks and read once the launch's run() has returned (its executor
// threads joined); active() may be read from any thread.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::bench {

// One message as the probe saw it.
struct StampTime {
  int64_t stamp_ns = 0;         // the capture stamp it carries
  int64_t publish_mono_ns = 0;  // when its publisher published it (monotonic clock)
};

class FrameCapture final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "bench: keeps a robot's stereo pairs and their poses in memory (bench pipeline)";
  struct Config {
    std::string robot_ns = "r1";
    uint32_t frames = 100;  // stops keeping pairs after this many
  };
  static Config read_config(ParamReader& p);
  FrameCapture(ComponentContext context, Config config);

  struct Pair {
    msg::StereoFrame frame;
    msg::Odometry pose;
  };
  // Pairs whose pose arrived, in capture order (call from the launch's thread).
  size_t pairs_captured() const { return pairs_.size(); }
  std::vector<Pair> take_pairs() { return std::move(pairs_); }

 private:
  Result<void, std::string> on_configure() override;
  void match();

  Config config_;
  std::vector<msg::StereoFrame> frames_;  // waiting for the pose of their stamp
  std::vector<msg::Odometry> poses_;
  std::vector<Pair> pairs_;
};

class PipelineProbe final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "bench: records stamps and publish times of depth, map, clusters, plan (bench pipeline)";
  struct Config {
    std::string robot_ns = "r1";
    std::string plan_topic = "/plan";
    uint32_t capacity = 20000;  // records reserved per topic (more still fit: allocates)
  };
  static Config read_config(ParamReader& p);
  PipelineProbe(ComponentContext context, Config config);

  // True between activation and deactivation.
  bool active() const { return active_.load(std::memory_order_acquire); }
  const std::vector<StampTime>& depth() const { return depth_; }
  const std::vector<StampTime>& maps() const { return maps_; }
  const std::vector<StampTime>& clusters() const { return clusters_; }
  const std::vector<StampTime>& plans() const { return plans_; }

 private:
  Result<void, std::string> on_configure() override;
  void on_activate() override { active_.store(true, std::memory_order_release); }
  void on_deactivate() override { active_.store(false, std::memory_order_release); }

  Config config_;
  std::atomic<bool> active_{false};
  std::vector<StampTime> depth_, maps_, clusters_, plans_;
};

}  // namespace scancrew::bench
