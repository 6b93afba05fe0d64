#pragma once

// One trial of `scancrew bench pipeline` (pipeline_bench.hpp): the stereo pairs of one
// drive, and the graph fed with them at a camera rate, measured stage by stage.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "bench/pipeline/pipeline_bench.hpp"
#include "bench/pipeline/pipeline_probe.hpp"
#include "core/result.hpp"

namespace scancrew::bench {

struct ImageSize {
  uint32_t width = 0, height = 0;
  // SGBM's disparity range scaled with the width, so both sizes see from the same depth on
  // (64 at 320 px: 0.65 m for the ground robot's rig; components/stereo_depth/stereo_depth.hpp)
  uint32_t num_disparities() const { return std::max(16u, (64u * width / 320u + 8u) / 16u * 16u); }
};

struct Figures {
  size_t n = 0;
  double p50 = 0, p99 = 0, max = 0;
};

struct Stage {
  std::string name, component, input, per;
  Figures callback_ms, from_input_ms, from_capture_ms;
};

struct Trial {
  double rate_hz = 0;         // asked
  double fed_rate_hz = 0;     // achieved by the feeding thread
  uint64_t pairs = 0;         // the camera's pairs
  uint64_t camera_drops = 0;  // no free slot in /r1/stereo's pool when the pair came
  uint64_t integrated = 0;    // depth images tsdf_mapper integrated
  uint64_t dropped = 0;       // pairs - integrated
  uint64_t stereo_queue_drops = 0, depth_queue_drops = 0;
  uint64_t snapshots = 0, ise_runs = 0, plans = 0;
  bool drained = true;
  double wall_s = 0;
  std::vector<Stage> stages;
  Figures end_to_end_ms;
  bool sustained() const { return dropped == 0 && drained; }
};

// 1. The stereo pairs and poses of one drive, rendered in lockstep.
Result<std::vector<FrameCapture::Pair>, std::string> capture(const PipelineBenchOptions& o,
                                                             const ImageSize& size,
                                                             uint32_t frames);

// 2. One trial: a fresh graph, the pairs at rate_hz on the wall clock.
Result<Trial, std::string> run_trial(const PipelineBenchOptions& o, const ImageSize& size,
                                     std::span<const FrameCapture::Pair> pairs, double rate_hz);

}  // namespace scancrew::bench
