// bench_reachable_truth: the cost of the reachable ground truth (eval/reachable_truth.hpp) on
// one scene, for one robot kind and its starts; prints the point counts, the free space and
// the wall-clock times of each stage (docs/evaluation.md, "Reachable ground truth").
//
//   bench_reachable_truth <scene.yaml> ground|multirotor "x,y,z[;x,y,z...]" [density_per_m2
//                         [pose_spacing_m [max_rays_per_point]]]
//
// The camera is the team simulator's default for the kind (ground: range [0.3, 5] m, 0.35 m
// up; multirotor: [1.6, 8] m, at the body centre); the body and altitude band default_body's.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "eval/reachable_truth.hpp"

int main(int argc, char** argv) {
  using namespace scancrew;
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: %s <scene.yaml> ground|multirotor \"x,y,z[;x,y,z...]\" [density [spacing "
                 "[rays]]]\n",
                 argv[0]);
    return 2;
  }
  const std::string kind_name = argv[2];
  if (kind_name != "ground" && kind_name != "multirotor") {
    std::fprintf(stderr, "kind must be ground or multirotor, not %s\n", argv[2]);
    return 2;
  }
  const auto kind =
      kind_name == "ground" ? robot::RobotKind::kGround : robot::RobotKind::kMultirotor;
  std::vector<msg::Vec3> starts;
  std::stringstream list(argv[3]);
  for (std::string item; std::getline(list, item, ';');) {
    msg::Vec3 p;
    if (std::sscanf(item.c_str(), "%lf,%lf,%lf", &p.x, &p.y, &p.z) < 2) {
      std::fprintf(stderr, "a start is x,y,z, not '%s'\n", item.c_str());
      return 2;
    }
    starts.push_back(p);
  }
  sim::SamplingOptions sampling;
  sampling.density_per_m2 = argc > 4 ? std::atof(argv[4]) : 2000;
  sim::CameraSpec camera;
  if (kind == robot::RobotKind::kMultirotor) {
    camera.min_range_m = 1.6;
    camera.max_range_m = 8.0;
    camera.mount_up_m = 0.0;
  }
  eval::ReachableTruthOptions options;
  if (argc > 5) options.pose_spacing_m = std::atof(argv[5]);
  if (argc > 6) options.max_rays_per_point = std::atoi(argv[6]);
  const auto t0 = std::chrono::steady_clock::now();
  auto r = eval::scene_reachable_truth(argv[1], eval::default_body(kind), starts, camera, sampling,
                                       options);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!r) {
    std::fprintf(stderr, "%s\n", r.error().c_str());
    return 1;
  }
  const auto& t = r->reachable;
  std::printf("%s, %s, %zu start(s), %.0f points/m2\n", argv[1], kind_name.c_str(), starts.size(),
              sampling.density_per_m2);
  std::printf("points %zu, observable %zu (%.2f %%)\n", r->truth.points.size(), t.observable_count,
              100.0 * static_cast<double>(t.observable_count) /
                  static_cast<double>(std::max<size_t>(1, r->truth.points.size())));
  std::printf("free cells %zu, reachable %zu; poses %zu, buckets %zu, rays %llu\n", r->free_cells,
              r->reachable_cells, t.poses, t.buckets, static_cast<unsigned long long>(t.rays));
  for (size_t i = 0; i < r->start_free.size(); ++i)
    if (!r->start_free[i]) std::printf("start %zu: the body does not fit there\n", i);
  std::printf("time: free space %.2f s, reachable truth %.2f s, total with sampling %.2f s\n",
              r->seconds_free_space, r->seconds_rays, total);
  return 0;
}
