#include "cli/eval_command.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "core/io/ply.hpp"
#include "eval/missed_points.hpp"
#include "eval/reconstruction_error.hpp"
#include "executors/log.hpp"
#include "sim/mesh_io.hpp"
#include "sim/surface_sampler.hpp"

namespace scancrew::cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

constexpr std::array<eval::Facing, eval::kFacings> kFacingOrder{
    eval::Facing::kUp, eval::Facing::kSide, eval::Facing::kDown};
constexpr std::array<eval::MissBand, eval::kMissBands> kBandOrder{
    eval::MissBand::kNear, eval::MissBand::kOff, eval::MissBand::kHole};

double percent(size_t part, size_t whole) {
  return whole == 0 ? 0.0 : 100.0 * static_cast<double>(part) / static_cast<double>(whole);
}

// The missed points by distance to the mesh and by facing, in % of the missed points.
void print_miss_profile(const eval::MissProfile& m, size_t gt_points) {
  std::printf(
      "missed %zu points (%.2f %% of the ground truth), in %% of them, by the distance to the "
      "mesh\n(near: the mesh passes within 2 e_max = %.2f m, a surface placed off or a "
      "neighbouring one; off: within 4 e_max; hole: no mesh within 4 e_max) and the way they "
      "face\n(up / down: normal within 45 deg of +z / -z):\n",
      m.points, percent(m.points, gt_points), 2 * m.e_max_m);
  std::printf("  %-6s %7s %7s %7s %7s\n", "", "near", "off", "hole", "all");
  for (const eval::Facing f : kFacingOrder) {
    std::printf("  %-6s", eval::to_string(f));
    for (const eval::MissBand b : kBandOrder)
      std::printf(" %7.1f", percent(m.count(f, b), m.points));
    std::printf(" %7.1f\n", percent(m.facing_total(f), m.points));
  }
  std::printf("  %-6s", "all");
  for (const eval::MissBand b : kBandOrder)
    std::printf(" %7.1f", percent(m.band_total(b), m.points));
  std::printf(" %7.1f\n", m.points == 0 ? 0.0 : 100.0);
}

nlohmann::ordered_json miss_profile_json(const eval::MissProfile& m) {
  nlohmann::ordered_json out;
  out["points"] = m.points;
  for (const eval::Facing f : kFacingOrder) {
    nlohmann::ordered_json row;
    for (const eval::MissBand b : kBandOrder) row[eval::to_string(b)] = m.count(f, b);
    out[eval::to_string(f)] = row;
  }
  return out;
}

// Writes the ground-truth points the mesh did not cover to o.missed_path; their profile.
Result<eval::MissProfile, std::string> write_misses(const EvalOptions& o,
                                                    const io::TriangleMesh& mesh,
                                                    const sim::SurfaceSamples& truth,
                                                    const eval::ReconstructionError& r) {
  // the ground-truth points no part of the mesh came within e_max of (NaN error)
  std::vector<std::array<float, 3>> points, normals;
  for (size_t i = 0; i < r.point_error_m.size(); ++i)
    if (std::isnan(r.point_error_m[i])) {
      points.push_back(truth.points[i]);
      normals.push_back(truth.normals[i]);
    }
  const std::string about = "scancrew eval: ground-truth points not covered by " + o.mesh_path;
  if (auto w = io::write_ply(
          o.missed_path,
          {.positions = io::flat(points), .normals = io::flat(normals), .comments = {about}});
      !w)
    return make_unexpected(w.error());
  return eval::profile_misses(mesh, points, normals, r.e_max_m);
}

// The wall seconds of the ground-truth sampling and of the evaluation.
struct EvalTimes {
  double sampling_s = 0, eval_s = 0;
};

// Prints the scores as one JSON object.
void print_eval_json(const EvalOptions& o, const eval::ReconstructionError& r,
                     const EvalTimes& times, const std::optional<eval::MissProfile>& misses) {
  // insertion order, as documented in docs/evaluation.md; NaN figures are written as null
  nlohmann::ordered_json out;
  out["mesh"] = o.mesh_path;
  out["scene"] = o.scene_path;
  out["voxel_m"] = o.voxel_size_m;
  out["e_max_m"] = r.e_max_m;
  out["gt_points"] = r.gt_points;
  out["covered"] = r.covered;
  out["coverage"] = r.coverage;
  out["mean_error_m"] = r.mean_error_m;
  out["std_error_m"] = r.std_error_m;
  out["rmse_m"] = r.rmse_m;
  out["seconds"] = times.eval_s;
  out["status"] = eval::to_string(r.status);
  out["mesh_triangles"] = r.mesh_triangles;
  out["density_per_m2"] = o.density_per_m2;
  out["seed"] = o.seed;
  out["sampling_seconds"] = times.sampling_s;
  if (misses) out["missed"] = miss_profile_json(*misses);
  std::printf("%s\n", out.dump().c_str());
}

// Prints the scores as text, with the missed points' profile when there is one.
void print_eval_text(const EvalOptions& o, const std::string& scene_name,
                     const eval::ReconstructionError& r, const EvalTimes& times,
                     const std::optional<eval::MissProfile>& misses) {
  std::printf("scene '%s': %zu ground-truth points (%g points/m2, seed %llu, %.2f s)\n",
              scene_name.c_str(), r.gt_points, o.density_per_m2,
              static_cast<unsigned long long>(o.seed), times.sampling_s);
  std::printf("mesh %s: %zu triangles; voxel %g m, e_max %.4f m\n", o.mesh_path.c_str(),
              r.mesh_triangles, o.voxel_size_m, r.e_max_m);
  const std::string why =
      r.status == eval::EvalStatus::kOk ? "" : ": " + std::string(eval::to_string(r.status));
  std::printf("coverage %.2f %% (%zu of %zu points)%s\n", 100 * r.coverage, r.covered, r.gt_points,
              why.c_str());
  if (r.covered == 0)
    std::printf("error along the normals: undefined, no point covered (%.2f s)\n", times.eval_s);
  else
    std::printf("error along the normals: mean %+.4f m, std %.4f m, RMSE %.4f m (%.2f s)\n",
                r.mean_error_m, r.std_error_m, r.rmse_m, times.eval_s);
  if (misses) print_miss_profile(*misses, r.gt_points);
}

}  // namespace

int run_eval(const EvalOptions& o) {
  auto scene = sim::load_scene(o.scene_path);
  if (!scene) {
    std::fprintf(stderr, "scancrew eval: %zu error(s) in the scene\n", scene.error().size());
    for (const auto& e : scene.error())
      std::fprintf(stderr, "  %s\n", scancrew::log::printable(e).c_str());
    return 2;
  }
  // the mesh first: a wrong path fails before seconds of sampling
  const auto mesh = io::read_ply_mesh(o.mesh_path);
  if (!mesh) {
    std::fprintf(stderr, "scancrew eval: %s\n", scancrew::log::printable(mesh.error()).c_str());
    return 2;
  }

  const auto sampling_start = std::chrono::steady_clock::now();
  auto scene_meshes = sim::load_scene_meshes(*scene);
  if (!scene_meshes) {
    std::fprintf(stderr, "scancrew eval: %s\n",
                 scancrew::log::printable(scene_meshes.error()).c_str());
    return 2;
  }
  const auto truth = sim::sample_surfaces(
      *scene, *scene_meshes,
      {.density_per_m2 = o.density_per_m2, .seed = o.seed, .visibility_rays = o.visibility_rays});
  if (!truth) {
    std::fprintf(stderr, "scancrew eval: %s\n", scancrew::log::printable(truth.error()).c_str());
    return 2;
  }
  const double sampling_s = seconds_since(sampling_start);

  const auto eval_start = std::chrono::steady_clock::now();
  const auto r = eval::reconstruction_error(*mesh, truth->points, truth->normals,
                                            {.e_max_m = eval::max_error_for_voxel(o.voxel_size_m),
                                             .per_point_error = !o.missed_path.empty()});
  const double eval_s = seconds_since(eval_start);
  if (!r) {
    std::fprintf(stderr, "scancrew eval: %s: %s\n", o.mesh_path.c_str(),
                 scancrew::log::printable(r.error()).c_str());
    return 2;
  }
  std::optional<eval::MissProfile> misses;
  if (!o.missed_path.empty()) {
    auto profile = write_misses(o, *mesh, *truth, *r);
    if (!profile) {
      std::fprintf(stderr, "scancrew eval: %s\n",
                   scancrew::log::printable(profile.error()).c_str());
      return 2;
    }
    misses = *profile;
  }

  const EvalTimes times{.sampling_s = sampling_s, .eval_s = eval_s};
  if (o.json) {
    print_eval_json(o, *r, times, misses);
    return 0;
  }
  print_eval_text(o, scene->name, *r, times, misses);
  return 0;
}

void add_eval_command(CLI::App& app, CommandTable& table) {
  auto [eval, o] = table.add_with_options<EvalOptions>(
      app, "eval", "score a reconstructed mesh against a scene's ground truth: coverage, error",
      run_eval);
  eval->add_option("--mesh", o->mesh_path, "reconstructed mesh (.ply)")->required();
  eval->add_option("--scene", o->scene_path, "scene file (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  eval->add_option("--voxel", o->voxel_size_m,
                   "voxel size r_v, m; e_max = r_v*sqrt(3)/2 (default 0.2)")
      ->check(CLI::Range(1e-4, 100.0));
  eval->add_option("--density", o->density_per_m2, "ground-truth points per m2 (default 10000)");
  eval->add_option("--seed", o->seed, "ground-truth random seed (default 1)");
  eval->add_option("--visibility-rays", o->visibility_rays,
                   "ground truth: ray directions per point of the mesh visibility test, 0: off "
                   "(default 64)")
      ->check(CLI::Range(0, 100000));
  eval->add_option("--missed", o->missed_path,
                   "write the ground-truth points not covered to this PLY (with normals)");
  eval->add_flag("--json", o->json, "print one JSON object");
}

}  // namespace scancrew::cli
