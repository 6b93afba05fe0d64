#include "bench/ise/bench_maps.hpp"

#include <cstdio>
#include <utility>

namespace scancrew::bench {

tsdf::TsdfConfig parking_lot_tsdf() {
  tsdf::TsdfConfig t;
  t.voxel_m = 0.2;
  t.truncation_m = 3 * t.voxel_m;
  t.min_range_m = 0.3;
  t.max_range_m = 5.0;
  return t;
}

tsdf::TsdfConfig powerplant_tsdf() {
  tsdf::TsdfConfig t;
  t.voxel_m = 0.3;
  t.truncation_m = 3 * t.voxel_m;
  t.min_range_m = 1.6;
  t.max_range_m = 8.0;
  return t;
}

std::optional<sim::SceneSpec> load_scene_or_report(const std::string& path) {
  auto scene = sim::load_scene(path);
  if (!scene) {
    for (const auto& e : scene.error()) std::fprintf(stderr, "%s\n", e.c_str());
    return std::nullopt;
  }
  return std::move(scene).value();
}

Result<DepthSequence, std::string> render_parking_lot(const sim::SceneSpec& scene,
                                                      const std::string& scene_name,
                                                      const tsdf::TsdfConfig& tsdf, int frames,
                                                      uint64_t seed) {
  auto seq = render_depth_sequence(scene, {.width = 320,
                                           .height = 256,
                                           .frames = frames,
                                           .frame_period_s = 0.4,
                                           .min_range_m = tsdf.min_range_m,
                                           .max_range_m = tsdf.max_range_m,
                                           .seed = seed});
  if (!seq) return make_unexpected("rendering " + scene_name + " failed: " + seq.error());
  return seq;
}

Result<void, std::string> feed_sequence(const DepthSequence& sequence, const DepthFrameSink& sink) {
  for (size_t i = 0; i < sequence.depth_m.size(); ++i)
    if (auto r =
            sink(depth_frame(sequence.depth_m[i], sequence.intrinsics, sequence.T_world_cam[i]));
        !r)
      return r;
  return {};
}

FlightSequenceOptions powerplant_flight(const tsdf::TsdfConfig& tsdf, int frames, bool quick,
                                        uint64_t seed) {
  FlightSequenceOptions flight;
  flight.frames = frames;
  if (quick) {
    flight.lap_fraction = 0.1;
    flight.width = 376;
    flight.height = 217;
  }
  flight.min_range_m = tsdf.min_range_m;
  flight.max_range_m = tsdf.max_range_m;
  flight.seed = seed;
  return flight;
}

Result<FlightSummary, std::string> fly_lap_into(const sim::SceneSpec& scene,
                                                const FlightSequenceOptions& flight,
                                                const DepthFrameSink& sink) {
  return fly_lap(scene, flight, [&](const msg::DepthImage& d) {
    return sink(depth_frame(d.depth_m, d.intrinsics, d.T_world_cam));
  });
}

}  // namespace scancrew::bench
