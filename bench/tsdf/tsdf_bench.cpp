#include "bench/tsdf/tsdf_bench.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "bench/bench_stats.hpp"
#include "bench/common/report.hpp"
#include "bench/tsdf/depth_sequence.hpp"
#include "bench/tsdf/open3d_peer.hpp"
#include "bench/tsdf/tsdf_report.hpp"
#include "core/tsdf/integrator.hpp"
#include "core/tsdf/mesher.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "eval/reconstruction_error.hpp"
#include "interfaces/eigen_conversions.hpp"
#include "sim/surface_sampler.hpp"

namespace scancrew::bench {

namespace {

// What either system hands back for one configuration.
struct SystemRun {
  std::vector<double> integrate_ms;
  double mesh_ms = 0;
  io::TriangleMesh mesh;
  size_t blocks = 0;  // allocated blocks (scancrew: 8³ voxels; Open3D: volume units of 16³)
  size_t voxels_per_block = 0;
  size_t memory_bytes = 0;
  double prepare_ms = 0;  // Open3D only: the RGBDImage made from the depth, mean per frame
  // scancrew only, per frame: blocks that passed the frustum and tile tests, blocks and
  // voxels written
  double candidate_blocks_per_frame = 0, updated_blocks_per_frame = 0, updated_voxels_per_frame = 0;
};

struct Measured {
  SystemRun run;
  std::vector<double> run_means_ms;  // ms per frame of each repeat
  eval::ReconstructionError error;
};

#ifdef SCANCREW_WITH_OPEN3D
// RMSE of each system over the ground-truth points that both cover: the two systems' RMSEs
// compared on the same points (their own RMSEs are over different sets when their coverages
// differ).
std::pair<double, double> rmse_on_common_points(const eval::ReconstructionError& a,
                                                const eval::ReconstructionError& b) {
  double sa = 0, sb = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.point_error_m.size() && i < b.point_error_m.size(); ++i) {
    const float ea = a.point_error_m[i], eb = b.point_error_m[i];
    if (std::isnan(ea) || std::isnan(eb)) continue;
    sa += static_cast<double>(ea) * ea;
    sb += static_cast<double>(eb) * eb;
    ++n;
  }
  if (n == 0) return {std::nan(""), std::nan("")};
  return {std::sqrt(sa / static_cast<double>(n)), std::sqrt(sb / static_cast<double>(n))};
}

#endif

struct Case {
  double voxel_m = 0, range_m = 0;
  double truncation_m() const { return 3 * voxel_m; }
};

// Overrides of the TsdfConfig defaults (empty / 0: the default).
struct WeightOverride {
  std::string weight;
  double w_th = 0;
  double mesh_min_weight = 0;
};

Result<SystemRun, std::string> run_scancrew(const DepthSequence& seq, const Case& c,
                                            const WeightOverride& weight) {
  tsdf::TsdfConfig config;
  config.voxel_m = c.voxel_m;
  config.truncation_m = c.truncation_m();
  config.min_range_m = seq.min_range_m;
  config.max_range_m = c.range_m;
  if (weight.w_th > 0) config.w_th = weight.w_th;
  if (!weight.weight.empty()) {
    const auto named = value_of(tsdf::kTsdfWeightNames, weight.weight);
    if (!named) return make_unexpected(std::string("weight must be inverse_square or constant"));
    config.weight = *named;
  }
  if (const std::string problem = config.validate(); !problem.empty())
    return make_unexpected(problem);
  tsdf::TsdfMap map(config);
  tsdf::Integrator integrator(config);
  const msg::CameraIntrinsics& k = seq.intrinsics;
  SystemRun run;
  run.integrate_ms.reserve(seq.depth_m.size());
  for (size_t i = 0; i < seq.depth_m.size(); ++i) {
    const tsdf::DepthFrame frame = depth_frame(seq.depth_m[i], k, seq.T_world_cam[i]);
    const auto t0 = Clock::now();
    const auto stats = integrator.integrate(map, frame);
    run.integrate_ms.push_back(ms_since(t0));
    if (!stats) return make_unexpected("frame " + std::to_string(i) + ": " + stats.error());
    run.candidate_blocks_per_frame += static_cast<double>(stats->candidate_blocks);
    run.updated_blocks_per_frame += static_cast<double>(stats->updated_blocks);
    run.updated_voxels_per_frame += static_cast<double>(stats->updated_voxels);
  }
  const auto n = static_cast<double>(std::max<size_t>(1, seq.depth_m.size()));
  run.candidate_blocks_per_frame /= n;
  run.updated_blocks_per_frame /= n;
  run.updated_voxels_per_frame /= n;
  const auto t0 = Clock::now();
  const auto snapshot = map.snapshot();
  tsdf::MesherConfig mesher_config;
  if (weight.mesh_min_weight > 0) mesher_config.min_weight = weight.mesh_min_weight;
  tsdf::Mesher mesher(mesher_config);
  mesher.full(*snapshot);
  const tsdf::Mesh mesh = mesher.assemble();
  run.mesh_ms = ms_since(t0);
  run.mesh.vertices.reserve(mesh.vertices.size());
  for (const Eigen::Vector3f& v : mesh.vertices) run.mesh.vertices.push_back({v.x(), v.y(), v.z()});
  run.mesh.triangles.assign(mesh.triangles.begin(), mesh.triangles.end());
  run.blocks = map.block_count();
  run.voxels_per_block = tsdf::kBlockVoxels;
  run.memory_bytes = map.memory_bytes();
  return run;
}

#ifdef SCANCREW_WITH_OPEN3D
Result<SystemRun, std::string> run_peer(const DepthSequence& seq, const Case& c) {
  const msg::CameraIntrinsics& k = seq.intrinsics;
  std::vector<PeerFrame> frames(seq.depth_m.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    frames[i].depth_m = seq.depth_m[i].data();
    // row-major: Eigen's default storage is column-major
    const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> T_cam_world =
        msg::to_eigen(seq.T_world_cam[i]).inverse().matrix();
    std::copy(T_cam_world.data(), T_cam_world.data() + 16, frames[i].T_cam_world.begin());
  }
  auto peer = run_open3d(
      {k.width, k.height, k.fx, k.fy, k.cx, k.cy}, frames,
      {.voxel_m = c.voxel_m, .truncation_m = c.truncation_m(), .max_range_m = c.range_m});
  if (!peer) return make_unexpected(peer.error());
  SystemRun run;
  run.integrate_ms = std::move(peer->integrate_ms);
  run.mesh_ms = peer->mesh_ms;
  run.mesh = std::move(peer->mesh);
  run.blocks = peer->volume_units;
  run.voxels_per_block = peer->voxels_per_unit;
  run.memory_bytes = peer->memory_bytes;
  run.prepare_ms = mean(peer->prepare_ms);
  return run;
}
#endif

Json row(const char* system, const DepthSequence& seq, const Case& c, const Measured& m,
         int threads) {
  const SystemRun& run = m.run;
  const eval::ReconstructionError& e = m.error;
  const double area_m2 = run.mesh.area();
  Json r;
  r["system"] = system;
  r["width"] = seq.intrinsics.width;
  r["height"] = seq.intrinsics.height;
  r["voxel_m"] = c.voxel_m;
  r["range_m"] = c.range_m;
  r["ms_per_frame"] = mean(run.integrate_ms);
  r["coverage"] = e.coverage;
  r["rmse_m"] = e.rmse_m;
  r["mean_error_m"] = e.mean_error_m;
  r["std_error_m"] = e.std_error_m;
  r["ms_p95"] = percentile(run.integrate_ms, 0.95);
  r["ms_max"] = run.integrate_ms.empty()
                    ? 0.0
                    : *std::max_element(run.integrate_ms.begin(), run.integrate_ms.end());
  r["ms_per_frame_runs"] = m.run_means_ms;
  r["mesh_ms"] = run.mesh_ms;
  r["mesh_triangles"] = run.mesh.triangles.size();
  r["mesh_area_m2"] = area_m2;
  r["memory_bytes"] = run.memory_bytes;
  r["bytes_per_m2"] = area_m2 > 0 ? static_cast<double>(run.memory_bytes) / area_m2 : 0.0;
  r["blocks"] = run.blocks;
  r["voxels_per_block"] = run.voxels_per_block;
  if (run.prepare_ms > 0) r["prepare_ms"] = run.prepare_ms;
  if (run.candidate_blocks_per_frame > 0) {
    r["candidate_blocks_per_frame"] = run.candidate_blocks_per_frame;
    r["updated_blocks_per_frame"] = run.updated_blocks_per_frame;
    r["updated_voxels_per_frame"] = run.updated_voxels_per_frame;
  }
  r["truncation_m"] = c.truncation_m();
  r["frames"] = run.integrate_ms.size();
  r["threads"] = threads;
  r["eval_status"] = std::string(eval::to_string(e.status));
  return r;
}

using Size = std::pair<uint32_t, uint32_t>;

// The image sizes, voxel sizes and ranges to run, each configuration of the three a case.
struct Grid {
  std::vector<Size> sizes;
  std::vector<double> voxels, ranges;
};

// The grid the options ask for (the defaults, or the quick run's); nullopt (after a message)
// when a size is not WxH.
std::optional<Grid> grid_for(const TsdfBenchOptions& o) {
  Grid g;
  g.sizes = o.quick ? std::vector<Size>{{320, 256}} : std::vector<Size>{{320, 256}, {640, 480}};
  g.voxels = o.quick ? std::vector<double>{0.2} : std::vector{0.1, 0.2, 0.3};
  g.ranges = o.quick ? std::vector<double>{5.0} : std::vector{5.0, 8.0};
  if (!o.sizes.empty()) {
    g.sizes.clear();
    for (const std::string& s : o.sizes) {
      unsigned w = 0, h = 0;
      char x = 0;
      if (std::sscanf(s.c_str(), "%u%c%u", &w, &x, &h) != 3 || x != 'x' || w < 16 || h < 16 ||
          w > 4096 || h > 4096) {
        std::fprintf(stderr, "bench tsdf: --sizes wants WxH (16..4096), got '%s'\n", s.c_str());
        return std::nullopt;
      }
      g.sizes.emplace_back(w, h);
    }
  }
  if (!o.voxels_m.empty()) g.voxels = o.voxels_m;
  if (!o.ranges_m.empty()) g.ranges = o.ranges_m;
  return g;
}

// Samples the scene's surfaces (meshes included) and reports the time taken on stderr.
Result<sim::SurfaceSamples, std::string> ground_truth(const sim::SceneSpec& scene,
                                                      const TsdfBenchOptions& o) {
  auto t0 = Clock::now();
  auto meshes = sim::load_scene_meshes(scene);
  if (!meshes) return make_unexpected(meshes.error());
  auto truth =
      sim::sample_surfaces(scene, *meshes, {.density_per_m2 = o.density_per_m2, .seed = o.seed});
  if (!truth) return make_unexpected(truth.error());
  std::fprintf(stderr, "ground truth: %zu points (%.0f m2) in %.1f s\n", truth->points.size(),
               truth->area_m2, ms_since(t0) * 1e-3);
  return truth;
}

// What every case shares: the options, the repeat count, the ground truth, the threads.
struct Setup {
  const TsdfBenchOptions& o;
  int frames = 0;
  int repeats = 1;
  const sim::SurfaceSamples& truth;
  int tbb_threads = 0, o3d_threads = 0;
  std::string o3d_name;
};

// The output's header: the scene, the run's settings, the ground truth and scancrew's TSDF
// settings, with empty result lists.
Json header(const Setup& b, const std::string& scene_name) {
  const TsdfBenchOptions& o = b.o;
  Json out;
  out["results"] = Json::array();
  out["comparisons"] = Json::array();
  out["scene"] = scene_name;
  out["frames"] = b.frames;
  out["repeats"] = b.repeats;
  out["threads"] = {{"scancrew_tbb", b.tbb_threads}, {"open3d_openmp", b.o3d_threads}};
  out["open3d"] = b.o3d_name;
  out["ground_truth"] = {{"points", b.truth.points.size()},
                         {"area_m2", b.truth.area_m2},
                         {"density_per_m2", o.density_per_m2},
                         {"seed", o.seed}};
  tsdf::TsdfConfig defaults;
  out["scancrew_tsdf"] = {
      {"weight",
       o.weight.empty() ? std::string(name_of(tsdf::kTsdfWeightNames, defaults.weight)) : o.weight},
      {"w_th", o.w_th > 0 ? o.w_th : defaults.w_th},
      {"max_weight", defaults.max_weight},
      {"tile_px", defaults.tile_px},
      {"truncation_voxels", 3},
      {"mesh_min_weight", tsdf::MesherConfig{}.min_weight}};
  if (o.mesh_min_weight > 0) out["scancrew_tsdf"]["mesh_min_weight"] = o.mesh_min_weight;
  out["load_average_1min"] = Json::array({load_average()});
  out["sequences"] = Json::array();
  out["targets"] = Json::array();
  return out;
}

// a system run `repeats` times on the sequence: the frame times of its fastest run (the
// least disturbed by other processes), its fastest meshing, the first run's mesh scored
// against the ground truth (runs are deterministic)
template <class RunOnce>
Result<Measured, std::string> measure(const Setup& b, RunOnce&& run_once, const Case& c) {
  Measured m;
  for (int i = 0; i < b.repeats; ++i) {
    auto run = run_once();
    if (!run) return make_unexpected(run.error());
    const double ms = mean(run->integrate_ms);
    m.run_means_ms.push_back(ms);
    if (i == 0) {
      m.run = std::move(run).value();
    } else {
      if (ms < mean(m.run.integrate_ms)) m.run.integrate_ms = run->integrate_ms;
      m.run.mesh_ms = std::min(m.run.mesh_ms, run->mesh_ms);
    }
  }
  auto e = eval::reconstruction_error(
      m.run.mesh, b.truth.points, b.truth.normals,
      {.e_max_m = eval::max_error_for_voxel(c.voxel_m), .per_point_error = true});
  if (!e) return make_unexpected("evaluation: " + e.error());
  m.error = std::move(e).value();
  return m;
}

#ifdef SCANCREW_WITH_OPEN3D
// Runs the Open3D peer on the case, appends its row and its comparison with scancrew's to
// out; false (after a message) when the peer fails.
bool compare_with_peer(const Setup& b, const DepthSequence& seq, Size size, const Case& c,
                       const Measured& ours, const Json& ours_row, Json& out) {
  const auto [w, h] = size;
  const double v = c.voxel_m, r = c.range_m;
  const auto peer = measure(
      b, [&] { return run_peer(seq, c); }, c);
  if (!peer) {
    std::fprintf(stderr, "; open3d failed: %s\n", peer.error().c_str());
    return false;
  }
  const Json peer_row = row("open3d", seq, c, *peer, b.o3d_threads);
  out["results"].push_back(peer_row);
  std::fprintf(stderr, "; open3d %.2f ms/frame, coverage %.3f",
               peer_row["ms_per_frame"].get<double>(), peer_row["coverage"].get<double>());
  const double speedup =
      peer_row["ms_per_frame"].get<double>() / ours_row["ms_per_frame"].get<double>();
  const auto common = rmse_on_common_points(ours.error, peer->error);
  std::fprintf(stderr, "; rmse on common points %.2f / %.2f mm", common.first * 1e3,
               common.second * 1e3);
  const bool accuracy =
      ours.error.coverage >= peer->error.coverage && ours.error.rmse_m <= peer->error.rmse_m;
  out["comparisons"].push_back(
      {{"width", w},
       {"height", h},
       {"voxel_m", v},
       {"range_m", r},
       {"speedup", speedup},
       {"mesh_speedup", peer->run.mesh_ms / ours.run.mesh_ms},
       {"coverage_diff", ours.error.coverage - peer->error.coverage},
       {"rmse_diff_m", ours.error.rmse_m - peer->error.rmse_m},
       {"rmse_common_m", {{"scancrew", common.first}, {"open3d", common.second}}},
       {"memory_ratio",
        static_cast<double>(ours.run.memory_bytes) / static_cast<double>(peer->run.memory_bytes)},
       {"at_least_2x_faster", speedup >= 2.0},
       {"equal_or_better_accuracy", accuracy}});
  return true;
}
#endif

// Runs scancrew (and the Open3D peer where built) on one case of the sequence and appends
// the rows to out, progress on stderr; false (after a message) when a system fails.
bool run_case(const Setup& b, const DepthSequence& seq, Size size, const Case& c, Json& out) {
  const TsdfBenchOptions& o = b.o;
  std::fprintf(stderr, "%ux%u voxel %.1f m range %.0f m:", size.first, size.second, c.voxel_m,
               c.range_m);
  const auto ours = measure(
      b,
      [&] {
        return run_scancrew(seq, c, {o.weight, o.w_th, o.mesh_min_weight});
      },
      c);
  if (!ours) {
    std::fprintf(stderr, " scancrew failed: %s\n", ours.error().c_str());
    return false;
  }
  const Json ours_row = row("scancrew", seq, c, *ours, b.tbb_threads);
  out["results"].push_back(ours_row);
  std::fprintf(stderr, " scancrew %.2f ms/frame, coverage %.3f",
               ours_row["ms_per_frame"].get<double>(), ours_row["coverage"].get<double>());
#ifdef SCANCREW_WITH_OPEN3D
  if (!compare_with_peer(b, seq, size, c, *ours, ours_row, out)) return false;
#endif
  std::fprintf(stderr, "\n");
  return true;
}

}  // namespace

int run_tsdf_bench(const TsdfBenchOptions& o) {
  auto scene = sim::load_scene(o.scene_path);
  if (!scene) {
    for (const auto& e : scene.error()) std::fprintf(stderr, "%s\n", e.c_str());
    return 2;
  }
  const int frames = o.frames > 0 ? o.frames : (o.quick ? 10 : 60);
  const int repeats = std::max(1, o.repeats);
  const auto grid = grid_for(o);
  if (!grid) return 2;

  // ground truth, once
  const auto truth = ground_truth(*scene, o);
  if (!truth) {
    std::fprintf(stderr, "bench tsdf: %s\n", truth.error().c_str());
    return 2;
  }

  const int tbb_threads = tbb::this_task_arena::max_concurrency();
#ifdef SCANCREW_WITH_OPEN3D
  const int o3d_threads = open3d_threads();
  const std::string o3d_name = open3d_description();
#else
  const int o3d_threads = 0;
  const std::string o3d_name = "unavailable";
  std::fprintf(stderr, "bench tsdf: built without Open3D: the peer is unavailable\n");
#endif
  const Setup b{o, frames, repeats, *truth, tbb_threads, o3d_threads, o3d_name};

  Json out = header(b, scene->name);
  int failures = 0;
  for (const auto& [w, h] : grid->sizes) {
    const double max_range = *std::max_element(grid->ranges.begin(), grid->ranges.end());
    auto seq = render_depth_sequence(
        *scene,
        {.width = w, .height = h, .frames = frames, .max_range_m = max_range, .seed = o.seed});
    if (!seq) {
      std::fprintf(stderr, "bench tsdf: rendering %ux%u failed: %s\n", w, h, seq.error().c_str());
      return 1;
    }
    out["sequences"].push_back({{"width", w},
                                {"height", h},
                                {"frames", seq->depth_m.size()},
                                {"driven_m", seq->driven_m},
                                {"sim_s", seq->sim_s},
                                {"render_wall_s", seq->wall_s},
                                {"depth_range_m", {seq->min_range_m, seq->max_range_m}}});
    for (double v : grid->voxels)
      for (double r : grid->ranges)
        if (!run_case(b, *seq, {w, h}, Case{v, r}, out)) ++failures;
  }

  return finish_report(out, o.json, failures, add_targets, print_table);
}

}  // namespace scancrew::bench
