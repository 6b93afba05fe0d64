#pragma once

// The two maps the ISE and planner benches build: their scenes, their TSDF settings, and
// the depth frames they are built from, the parking lot's rendered sequence
// (bench/tsdf/depth_sequence.hpp) and the powerplant's multirotor lap (flight_sequence.hpp),
// each frame handed to a sink as the integrator takes it.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "bench/ise/flight_sequence.hpp"
#include "bench/tsdf/depth_sequence.hpp"
#include "core/result.hpp"
#include "core/tsdf/integrator.hpp"
#include "core/tsdf/tsdf_config.hpp"
#include "sim/scene.hpp"

namespace scancrew::bench {

// Thesis table 5.3 (parking lot, ground robots): 0.2 m voxels over the ground camera's
// range [0.3, 5] m.
tsdf::TsdfConfig parking_lot_tsdf();

// Thesis table 2.1 (powerplant, multirotors): 0.3 m voxels over the camera's range
// [1.6, 8] m.
tsdf::TsdfConfig powerplant_tsdf();

// The scene at `path`; nullopt after the loader's errors on stderr, one a line.
std::optional<sim::SceneSpec> load_scene_or_report(const std::string& path);

// Called with each frame (a view: valid during the call only); an error ends the feed.
using DepthFrameSink = std::function<Result<void, std::string>(const tsdf::DepthFrame& frame)>;

// The TSDF bench's loop around the parking lot at 320 × 256, a frame every 0.4 s (0.2 m)
// rather than its 1.5 s, over the map's depth range [tsdf.min_range_m, tsdf.max_range_m];
// progress on stderr. Fails with "rendering <scene_name> failed: <why>".
Result<DepthSequence, std::string> render_parking_lot(const sim::SceneSpec& scene,
                                                      const std::string& scene_name,
                                                      const tsdf::TsdfConfig& tsdf, int frames,
                                                      uint64_t seed);

// Hands each frame of `sequence` to `sink`, in order; fails with the sink's first error.
Result<void, std::string> feed_sequence(const DepthSequence& sequence, const DepthFrameSink& sink);

// The powerplant lap of `frames` frames over the map's depth range; `quick`: the first
// tenth of the lap at the same density, at 376 × 217 (f = 188 px).
FlightSequenceOptions powerplant_flight(const tsdf::TsdfConfig& tsdf, int frames, bool quick,
                                        uint64_t seed);

// Flies `flight` (fly_lap), handing each frame to `sink` as it is rendered; progress on
// stderr. Fails as fly_lap does, with the sink's first error among them.
Result<FlightSummary, std::string> fly_lap_into(const sim::SceneSpec& scene,
                                                const FlightSequenceOptions& flight,
                                                const DepthFrameSink& sink);

}  // namespace scancrew::bench
