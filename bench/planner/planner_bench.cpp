#include "bench/planner/planner_bench.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <utility>
#include <vector>

#include "bench/bench_stats.hpp"
#include "bench/common/report.hpp"
#include "bench/ise/bench_maps.hpp"
#include "bench/planner/query_endpoints.hpp"
#include "core/motion/motion_planner.hpp"
#include "core/motion/obstacle_geometry.hpp"
#include "core/tsdf/integrator.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "interfaces/eigen_conversions.hpp"
#include "sim/mesh_io.hpp"
#include "sim/robot_model.hpp"
#include "sim/scene.hpp"

namespace scancrew::bench {

namespace {

using Json = nlohmann::ordered_json;
using motion::MotionPlanner;
using motion::PlannerConfig;
using motion::PlanResult;
using motion::PlanStatus;

constexpr double kMedianTargetMs = 50;
// query ends: when fewer of the robot's own poses are free, random free positions are drawn
constexpr size_t kMinEndpoints = 20, kRandomEndpoints = 400;

struct Case {
  std::string scene;
  tsdf::TsdfConfig tsdf;
  PlannerConfig planner;
  double min_query_m = 0;   // query ends at least this far apart
  double check_step_m = 0;  // ground-truth sampling along the path
};

Case parking_lot_case(uint64_t seed) {
  Case c;
  c.scene = "parking_lot";
  c.tsdf = parking_lot_tsdf();
  c.planner.robot_kind = robot::RobotKind::kGround;  // table 5.3 body, the defaults
  c.planner.body_margin_m = 0.5 * c.tsdf.voxel_m;
  c.planner.unknown_is_occupied = true;
  c.planner.seed = seed;
  c.min_query_m = 3.0;
  c.check_step_m = 0.02;
  return c;
}

Case powerplant_case(uint64_t seed) {
  Case c;
  c.scene = "powerplant";
  c.tsdf = powerplant_tsdf();
  c.planner.robot_kind = robot::RobotKind::kMultirotor;  // table 2.1: 1 m sphere
  c.planner.body_margin_m = 0.5 * c.tsdf.voxel_m;
  // the lap's map has no connected free space for the 1 m sphere when unknown space
  // collides (measured: no path at all), and the multirotor's own corridor is never in view:
  // unknown is free here, as for the ISE's multirotor viewpoints; paths may then cross parts
  // of the plant no frame saw (counted apart: paths_through_unknown)
  c.planner.unknown_is_occupied = false;
  c.planner.multirotor_min_altitude_m = 2.0;
  c.planner.multirotor_max_altitude_m = 12.0;
  c.planner.collision_check_step_m = 0.15;
  c.planner.seed = seed;
  c.min_query_m = 15.0;
  c.check_step_m = 0.05;
  return c;
}

// The robot's pose under a camera: heading along the optical axis; a ground robot's body
// frame is on the floor, mount_forward_m behind the camera; a multirotor's camera is at
// its centre (flight_sequence.hpp).
msg::Waypoint robot_pose(const Eigen::Isometry3d& T_world_cam, bool ground) {
  const Eigen::Vector3d forward = T_world_cam.linear().col(2);
  const double yaw = std::atan2(forward.y(), forward.x());
  Eigen::Vector3d p = T_world_cam.translation();
  if (ground) {
    p -= sim::CameraSpec{}.mount_forward_m * Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0);
    p.z() = 0;
  }
  msg::Waypoint w;
  w.position = {p.x(), p.y(), p.z()};
  w.yaw_rad = yaw;
  return w;
}

// The scene as build_mjcf() places it: boxes, cylinders, walls, ceiling, floor, meshes.
Result<motion::ObstacleGeometry, std::string> ground_truth(const sim::SceneSpec& s) {
  motion::ObstacleGeometry g;
  auto v = [](const msg::Vec3& p) { return Eigen::Vector3d(p.x, p.y, p.z); };
  const double sx = s.max_m.x - s.min_m.x, sy = s.max_m.y - s.min_m.y;
  const double cx = 0.5 * (s.min_m.x + s.max_m.x), cy = 0.5 * (s.min_m.y + s.max_m.y);
  g.add_box({cx, cy, -0.05}, {sx + 2, sy + 2, 0.1});  // floor
  if (s.ceiling) g.add_box({cx, cy, s.max_m.z + 0.05}, {sx + 0.4, sy + 0.4, 0.1});
  if (s.wall_height_m > 0) {
    const double t = s.wall_thickness_m, h = s.wall_height_m;
    g.add_box({cx, s.max_m.y + 0.5 * t, 0.5 * h}, {sx + 2 * t, t, h});
    g.add_box({cx, s.min_m.y - 0.5 * t, 0.5 * h}, {sx + 2 * t, t, h});
    g.add_box({s.max_m.x + 0.5 * t, cy, 0.5 * h}, {t, sy, h});
    g.add_box({s.min_m.x - 0.5 * t, cy, 0.5 * h}, {t, sy, h});
  }
  for (const sim::BoxSpec& b : s.boxes) g.add_box(v(b.center_m), v(b.size_m), b.yaw_rad);
  for (const sim::CylinderSpec& c : s.cylinders)
    g.add_cylinder(v(c.center_m), c.radius_m, c.height_m);
  if (!s.meshes.empty()) {
    auto meshes = sim::load_scene_meshes(s);
    if (!meshes) return make_unexpected(meshes.error());
    for (const io::TriangleMesh& m : *meshes) {
      std::vector<Eigen::Vector3d> vertices;
      vertices.reserve(m.vertices.size());
      for (const msg::Vec3& p : m.vertices) vertices.push_back(v(p));
      g.add_mesh(vertices, m.triangles);
    }
  }
  return g;
}

// The map as the robot builds it, followed by a planner (update_map() per snapshot).
struct Run {
  tsdf::TsdfMap map;
  tsdf::Integrator integrator;
  MotionPlanner planner;
  std::vector<msg::Waypoint> poses;
  std::vector<double> update_ms;
  std::shared_ptr<const tsdf::MapSnapshot> last;
  bool ground;

  Result<void, std::string> add(const tsdf::DepthFrame& f) {
    last.reset();
    if (auto s = integrator.integrate(map, f); !s) return make_unexpected(s.error());
    last = map.snapshot();
    update_ms.push_back(planner.update_map(last, 0).ms);
    poses.push_back(robot_pose(f.T_world_cam, ground));
    return {};
  }
};

Json figures(const std::vector<double>& ms) {
  return {{"median", percentile(ms, 0.5)},
          {"p95", percentile(ms, 0.95)},
          {"max", max_of(ms)},
          {"n", ms.size()}};
}

struct Tally {
  std::vector<double> ms;
  std::vector<double> roadmap_ms;  // the queries that needed the roadmap (not a straight motion)
  size_t ok = 0, direct = 0, checked = 0, colliding = 0;
  std::vector<size_t> by_status =
      std::vector<size_t>(static_cast<size_t>(PlanStatus::kBadInput) + 1, 0);
  double length_m = 0;
  size_t through_unknown = 0, colliding_known = 0;
  // strict: a planner on the same map with unknown space occupied, to tell paths that
  // cross unknown space from those in known free space
  void add(const PlanResult& r, const motion::ObstacleGeometry& truth, const Case& c,
           const MotionPlanner& strict) {
    ms.push_back(r.stats.total_ms);
    ++by_status[static_cast<size_t>(r.status)];
    if (r.status != PlanStatus::kOk) return;
    ++ok;
    direct += r.stats.direct ? 1 : 0;
    if (!r.stats.direct) roadmap_ms.push_back(r.stats.total_ms);
    length_m += r.stats.length_m;
    PlannerConfig bare = c.planner;
    bare.body_margin_m = 0;
    const motion::PathCheck check =
        truth.check_path(c.planner, motion::body_of(bare), r.path, c.check_step_m);
    ++checked;
    colliding += check.colliding > 0 ? 1 : 0;
    bool known = true;
    for (size_t i = 1; i < r.path.size() && known; ++i) {
      const msg::Waypoint& a = r.path[i - 1];
      const msg::Waypoint& b = r.path[i];
      const double d = std::hypot(b.position.x - a.position.x, b.position.y - a.position.y,
                                  b.position.z - a.position.z);
      const int n = std::max(1, static_cast<int>(std::ceil(d / c.check_step_m)));
      for (int k = 0; k <= n && known; ++k) {
        const double t = static_cast<double>(k) / n;
        msg::Waypoint w = a;
        w.position = {a.position.x + t * (b.position.x - a.position.x),
                      a.position.y + t * (b.position.y - a.position.y),
                      a.position.z + t * (b.position.z - a.position.z)};
        w.yaw_rad = a.yaw_rad + t * std::remainder(b.yaw_rad - a.yaw_rad, 2 * M_PI);
        known = strict.is_free(w);
      }
    }
    through_unknown += known ? 0 : 1;
    colliding_known += known && check.colliding > 0 ? 1 : 0;
  }
  Json statuses() const {
    Json j;
    for (size_t i = 0; i < by_status.size(); ++i)
      if (by_status[i] > 0)
        j[std::string(motion::to_string(static_cast<PlanStatus>(i)))] = by_status[i];
    return j;
  }
};

Json run_queries(const Case& c, Run& run, const motion::ObstacleGeometry& truth, int queries,
                 int firsts, uint64_t seed) {
  // query ends: the robot's poses that are free in the final map
  std::vector<msg::Waypoint> free = free_robot_poses(run.poses, c.planner, run.planner);
  size_t truly_colliding = 0;  // free in the map, not in the true geometry (should be none)
  PlannerConfig bare = c.planner;
  bare.body_margin_m = 0;
  const robot::BodyModel true_body = motion::body_of(bare);
  // too few (the multirotor's own lap is never in its camera's view, so with unknown space
  // occupied none of its poses is free): free positions drawn in the map's box instead
  std::mt19937_64 rng(seed);
  const size_t robot_poses = free.size();
  if (free.size() < kMinEndpoints)
    add_random_free_positions(*run.last, c.planner, run.planner, kRandomEndpoints, rng, free);
  for (const msg::Waypoint& p : free)
    if (truth.collides(true_body, motion::body_pose(c.planner, p))) ++truly_colliding;
  const size_t wanted_pairs = static_cast<size_t>(queries) + static_cast<size_t>(firsts);
  const std::vector<std::pair<msg::Waypoint, msg::Waypoint>> pairs =
      draw_query_pairs(free, wanted_pairs, c.min_query_m, rng);
  Json j;
  j["free_poses"] = free.size();
  j["robot_poses_free"] = robot_poses;
  j["free_poses_colliding"] = truly_colliding;
  if (pairs.size() < wanted_pairs) {
    j["error"] = "too few free poses to draw the queries from";
    return j;
  }
  PlannerConfig strict_config = c.planner;
  strict_config.unknown_is_occupied = true;
  auto strict = MotionPlanner::create(strict_config);
  if (!strict) return {{"error", strict.error()}};
  strict->update_map(run.last, 0);
  // reused: the planner that followed the map, one query after the other
  Tally reused;
  std::vector<std::pair<msg::Waypoint, msg::Waypoint>> hard;  // those that needed the roadmap
  for (int i = 0; i < queries; ++i) {
    const auto& [a, b] = pairs[static_cast<size_t>(i)];
    const PlanResult r = run.planner.plan({a, b, 0});
    reused.add(r, truth, c, *strict);
    if (r.status == PlanStatus::kOk && !r.stats.direct) hard.emplace_back(a, b);
  }
  // first queries: a fresh planner (empty roadmap) on the final map each time, on queries
  // that needed the roadmap above (a straight motion would not build one)
  Tally first;
  std::vector<double> build_ms;
  for (int i = 0; i < firsts; ++i) {
    auto fresh = MotionPlanner::create(c.planner);
    if (!fresh) return {{"error", fresh.error()}};
    build_ms.push_back(fresh->update_map(run.last, 0).ms);
    const auto& [a, b] = hard.empty() ? pairs[static_cast<size_t>(queries) + static_cast<size_t>(i)]
                                      : hard[static_cast<size_t>(i) % hard.size()];
    first.add(fresh->plan({a, b, 0}), truth, c, *strict);
  }
  const size_t checked = first.checked + reused.checked;
  const size_t colliding = first.colliding + reused.colliding;
  j["first_query_ms"] = figures(first.ms);
  j["reused_ms"] = figures(reused.ms);
  j["reused_roadmap_ms"] = figures(reused.roadmap_ms);  // the direct ones left out
  j["paths_checked"] = checked;
  j["paths_colliding"] = colliding;
  j["paths_through_unknown"] = first.through_unknown + reused.through_unknown;
  j["paths_in_known_space_colliding"] = first.colliding_known + reused.colliding_known;
  j["first_statuses"] = first.statuses();
  j["reused_statuses"] = reused.statuses();
  j["reused_ok"] = reused.ok;
  j["reused_direct"] = reused.direct;
  j["reused_mean_length_m"] = reused.ok > 0 ? reused.length_m / static_cast<double>(reused.ok) : 0;
  j["roadmap_vertices"] = run.planner.roadmap_vertices();
  j["octree_build_ms"] = figures(build_ms);
  return j;
}

void add_targets(Json& out) {
  auto verdict = [](double ms) { return ms <= kMedianTargetMs ? "met" : "missed"; };
  for (const Json& r : out["results"]) {
    if (!r.contains("reused_ms")) continue;
    const double first = r["first_query_ms"]["median"].get<double>();
    const double reused = r["reused_ms"]["median"].get<double>();
    const double roadmap = r["reused_roadmap_ms"]["median"].get<double>();
    const bool any_roadmap = r["reused_roadmap_ms"]["n"].get<size_t>() > 0;
    char line[320];
    std::snprintf(line, sizeof line,
                  "%s %s: median query <= %.0f ms: reused roadmap %.1f ms (%s), of those through "
                  "the roadmap %.1f ms (%s), first query %.1f ms (%s); %zu of %zu paths collide "
                  "with the true geometry",
                  r["scene"].get<std::string>().c_str(), r["robot"].get<std::string>().c_str(),
                  kMedianTargetMs, reused, verdict(reused), roadmap,
                  any_roadmap ? verdict(roadmap) : "no query needed it", first, verdict(first),
                  r["paths_colliding"].get<size_t>(), r["paths_checked"].get<size_t>());
    out["targets"].push_back(line);
  }
}

void print_table(const Json& out) {
  std::printf(
      "Low-level planner (LazyPRM* + FCL octree), query time in ms: median / p95 / max\n\n");
  std::printf("%-12s %-10s %5s | %-22s | %-22s | %-22s | %8s %9s\n", "scene", "robot", "voxel",
              "first query", "reused roadmap (all)", "reused, via roadmap", "ok/direct",
              "colliding");
  auto cell = [](const Json& f) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%6.2f %6.2f %8.2f", f["median"].get<double>(),
                  f["p95"].get<double>(), f["max"].get<double>());
    return std::string(buf);
  };
  for (const Json& r : out["results"]) {
    if (!r.contains("reused_ms")) continue;
    std::printf("%-12s %-10s %5.1f | %-22s | %-22s | %-22s | %4zu/%-3zu %5zu/%zu\n",
                r["scene"].get<std::string>().c_str(), r["robot"].get<std::string>().c_str(),
                r["voxel_m"].get<double>(), cell(r["first_query_ms"]).c_str(),
                cell(r["reused_ms"]).c_str(), cell(r["reused_roadmap_ms"]).c_str(),
                r["reused_ok"].get<size_t>(), r["reused_direct"].get<size_t>(),
                r["paths_colliding"].get<size_t>(), r["paths_checked"].get<size_t>());
  }
  for (const Json& line : out["targets"]) std::printf("\n%s", line.get<std::string>().c_str());
  std::printf("\n");
}

bool wanted(const PlannerBenchOptions& o, const std::string& scene) {
  return o.scenes.empty() || std::find(o.scenes.begin(), o.scenes.end(), scene) != o.scenes.end();
}

// Builds the parking lot's map from the TSDF bench's depth sequence into run; false (after a
// message) when rendering or a frame fails.
bool feed_parking_lot(const sim::SceneSpec& scene, const Case& c, int frames, uint64_t seed,
                      Run& run) {
  const auto seq = render_parking_lot(scene, c.scene, c.tsdf, frames, seed);
  if (!seq) {
    std::fprintf(stderr, "bench planner: %s\n", seq.error().c_str());
    return false;
  }
  if (auto fed = feed_sequence(*seq, [&](const tsdf::DepthFrame& f) { return run.add(f); }); !fed) {
    std::fprintf(stderr, "bench planner: %s\n", fed.error().c_str());
    return false;
  }
  return true;
}

// Builds the powerplant's map from the ISE bench's lap into run, frame by frame; false
// (after a message) when the flight or a frame fails.
bool feed_powerplant(const sim::SceneSpec& scene, const Case& c, const PlannerBenchOptions& o,
                     int frames, Run& run) {
  const auto lap = fly_lap_into(scene, powerplant_flight(c.tsdf, frames, o.quick, o.seed),
                                [&](const tsdf::DepthFrame& f) { return run.add(f); });
  if (!lap) {
    std::fprintf(stderr, "bench planner: %s: %s\n", c.scene.c_str(), lap.error().c_str());
    return false;
  }
  return true;
}

// Adds the map's figures, the queries' and the planner's settings to row and reports it on
// stderr; false when the queries failed.
bool add_query_figures(const Case& c, Run& run, const motion::ObstacleGeometry& truth, int queries,
                       int firsts, uint64_t seed, Json& row) {
  row["frames"] = run.update_ms.size();
  row["map_blocks"] = run.last->block_count();
  row["map_update_ms"] = {{"mean", mean(run.update_ms)}, {"max", max_of(run.update_ms)}};
  row.update(run_queries(c, run, truth, queries, firsts, seed));
  row["body_radii_m"] = {motion::body_of(c.planner).safety_radii_m.x(),
                         motion::body_of(c.planner).safety_radii_m.y(),
                         motion::body_of(c.planner).safety_radii_m.z()};
  row["body_margin_m"] = c.planner.body_margin_m;
  row["unknown_is_occupied"] = c.planner.unknown_is_occupied;
  row["time_limit_s"] = c.planner.planner_time_limit_s;
  if (row.contains("error")) {
    std::fprintf(stderr, "bench planner: %s: %s\n", c.scene.c_str(),
                 row["error"].get<std::string>().c_str());
    return false;
  }
  std::fprintf(stderr, "%s: reused median %.2f ms (p95 %.2f), first %.2f ms; %zu/%zu colliding\n",
               c.scene.c_str(), row["reused_ms"]["median"].get<double>(),
               row["reused_ms"]["p95"].get<double>(), row["first_query_ms"]["median"].get<double>(),
               row["paths_colliding"].get<size_t>(), row["paths_checked"].get<size_t>());
  return true;
}

}  // namespace

int run_planner_bench(const PlannerBenchOptions& o) {
  const int parking_frames = o.frames > 0 ? o.frames : (o.quick ? 80 : 300);
  const int powerplant_frames = o.frames > 0 ? o.frames : (o.quick ? 100 : 1000);
  const int queries = o.queries > 0 ? o.queries : (o.quick ? 20 : 100);
  const int firsts = o.firsts > 0 ? o.firsts : (o.quick ? 3 : 10);
  for (const std::string& s : o.scenes)
    if (s != "parking_lot" && s != "powerplant") {
      std::fprintf(stderr, "bench planner: unknown scene '%s' (parking_lot, powerplant)\n",
                   s.c_str());
      return 2;
    }
  Json out;
  out["results"] = Json::array();
  out["targets"] = Json::array();
  out["seed"] = o.seed;
  out["load_average_1min"] = Json::array({load_average()});

  int failures = 0;
  for (const Case& c : {parking_lot_case(o.seed), powerplant_case(o.seed)}) {
    if (!wanted(o, c.scene)) continue;
    const bool parking = c.scene == "parking_lot";
    const auto scene = load_scene_or_report(parking ? o.parking_lot_path : o.powerplant_path);
    if (!scene) return 2;
    auto truth = ground_truth(*scene);
    if (!truth) {
      std::fprintf(stderr, "bench planner: %s: %s\n", c.scene.c_str(), truth.error().c_str());
      return 2;
    }
    auto planner = MotionPlanner::create(c.planner);
    if (!planner) {
      std::fprintf(stderr, "bench planner: %s: %s\n", c.scene.c_str(), planner.error().c_str());
      return 2;
    }
    Run run{tsdf::TsdfMap(c.tsdf),
            tsdf::Integrator(c.tsdf),
            std::move(planner).value(),
            {},
            {},
            nullptr,
            parking};
    Json row;
    row["scene"] = c.scene;
    row["robot"] = std::string(robot::to_string(c.planner.robot_kind));
    row["voxel_m"] = c.tsdf.voxel_m;
    const bool fed = parking ? feed_parking_lot(*scene, c, parking_frames, o.seed, run)
                             : feed_powerplant(*scene, c, o, powerplant_frames, run);
    if (!fed) return 1;
    if (!run.last) {
      std::fprintf(stderr, "bench planner: %s: no frame\n", c.scene.c_str());
      ++failures;
      continue;
    }
    if (!add_query_figures(c, run, *truth, queries, firsts, o.seed, row)) ++failures;
    out["results"].push_back(row);
  }
  return finish_report(out, o.json, failures, add_targets, print_table);
}

}  // namespace scancrew::bench
