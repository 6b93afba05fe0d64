#include "cli/groundtruth_command.hpp"

#include <chrono>
#include <cstdio>

#include "cli/commands.hpp"
#include "core/io/ply.hpp"
#include "executors/log.hpp"
#include "sim/mesh_io.hpp"
#include "sim/surface_sampler.hpp"

namespace scancrew::cli {

int run_groundtruth(const GroundTruthOptions& o) {
  auto scene = sim::load_scene(o.scene_path);
  if (!scene) {
    std::fprintf(stderr, "scancrew groundtruth: %zu error(s) in the scene\n", scene.error().size());
    for (const auto& e : scene.error())
      std::fprintf(stderr, "  %s\n", scancrew::log::printable(e).c_str());
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  auto meshes = sim::load_scene_meshes(*scene);
  if (!meshes) {
    std::fprintf(stderr, "scancrew groundtruth: %s\n",
                 scancrew::log::printable(meshes.error()).c_str());
    return 2;
  }
  auto samples = sim::sample_surfaces(
      *scene, *meshes,
      {.density_per_m2 = o.density_per_m2, .seed = o.seed, .visibility_rays = o.visibility_rays});
  if (!samples) {
    std::fprintf(stderr, "scancrew groundtruth: %s\n",
                 scancrew::log::printable(samples.error()).c_str());
    return 2;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  char about[256];
  std::snprintf(about, sizeof about,
                "scancrew groundtruth: scene %s, %g points/m2, seed %llu, visible area %.3f m2",
                scene->name.c_str(), o.density_per_m2, static_cast<unsigned long long>(o.seed),
                samples->area_m2);
  if (auto w = io::write_ply(o.out_path, {.positions = io::flat(samples->points),
                                          .normals = io::flat(samples->normals),
                                          .comments = {about}});
      !w) {
    std::fprintf(stderr, "scancrew groundtruth: %s\n", scancrew::log::printable(w.error()).c_str());
    return 2;
  }
  std::printf("scene '%s': %zu points, visible area %.2f m2 (%g points/m2, seed %llu, %.2f s)\n",
              scene->name.c_str(), samples->points.size(), samples->area_m2, o.density_per_m2,
              static_cast<unsigned long long>(o.seed), seconds);
  std::printf("wrote %s\n", o.out_path.c_str());
  return 0;
}

void add_groundtruth_command(CLI::App& app, CommandTable& table) {
  auto [groundtruth, o] = table.add_with_options<GroundTruthOptions>(
      app, "groundtruth", "sample points with normals on a scene's visible surfaces, as a PLY",
      run_groundtruth);
  groundtruth->add_option("scene", o->scene_path, "scene file (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  groundtruth->add_option("--out", o->out_path, "output file (.ply)")->required();
  groundtruth->add_option("--density", o->density_per_m2, "points per m2 (default 10000)");
  groundtruth->add_option("--seed", o->seed, "random seed (default 1)");
  groundtruth
      ->add_option("--visibility-rays", o->visibility_rays,
                   "ray directions per point of the mesh visibility test, 0: off (default 64)")
      ->check(CLI::Range(0, 100000));
}

}  // namespace scancrew::cli
