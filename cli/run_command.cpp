#include "cli/run_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "cli/mission_compose.hpp"
#include "cli/report.hpp"
#include "components/dds_bridge/dds_bridge.hpp"
#include "components/low_level/low_level_planner.hpp"
#include "components/mission/mission_monitor.hpp"
#include "components/team_simulator/team_simulator.hpp"
#include "components/tsdf/tsdf_mapper.hpp"
#include "eval/ply_mesh.hpp"
#include "eval/reconstruction_error.hpp"
#include "eval/team_reachable.hpp"
#include "executors/launch.hpp"
#include "executors/log.hpp"
#include "executors/trace.hpp"
#include "mission/run_files.hpp"
#include "mission/run_report.hpp"
#include "mission/time_breakdown.hpp"
#include "sim/mesh_io.hpp"
#include "sim/scene.hpp"
#include "sim/surface_sampler.hpp"

namespace scancrew::cli {

namespace {

namespace fs = std::filesystem;
using components::MissionMonitor;
using Json = nlohmann::ordered_json;

Launch* g_running = nullptr;

volatile std::sig_atomic_t g_interrupted = 0;

void on_signal(int /*signal*/) {
  g_interrupted = 1;
  if (g_running != nullptr) g_running->request_stop();
}

std::string local_time_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", &tm);
  return buf;
}

// NaN and infinities have no JSON form: null.
Json number_or_null(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

void print_mission_progress(const MissionMonitor& monitor, double elapsed_s, double duration_s,
                            double wall_s, bool final) {
  static const bool tty = isatty(fileno(stderr)) != 0;
  char head[96];
  std::snprintf(head, sizeof head, "t %6.1f / %.0f s  x%.1f  ", elapsed_s, duration_s,
                wall_s > 0 ? elapsed_s / wall_s : 0.0);
  std::fprintf(stderr, "%s%s%s%s", tty ? "\r\033[K" : "", head, monitor.status_line().c_str(),
               tty && !final ? "" : "\n");
  std::fflush(stderr);
}

// What a bridge sent and received: the data exchanged (thesis 5.4), per minute of sim time.
void print_bridge_bytes(const dds_bridge::DdsBridge& bridge, double sim_s) {
  const dds_bridge::BridgeStats s = bridge.stats();
  uint64_t sent = 0, received = 0, samples = 0;
  for (const auto& t : s.topics) {
    sent += t.sent_bytes;
    received += t.received_bytes;
    samples += t.sent_samples;
  }
  const double minutes = sim_s / 60.0;
  std::printf(
      "dds %s (bridge %u): sent %llu bytes in %llu samples (%.0f bytes per minute of sim "
      "time), received %llu bytes; peers lost %llu\n",
      bridge.qualified_name().c_str(), bridge.bridge_id(), static_cast<unsigned long long>(sent),
      static_cast<unsigned long long>(samples),
      minutes > 0 ? static_cast<double>(sent) / minutes : 0.0,
      static_cast<unsigned long long>(received), static_cast<unsigned long long>(s.peers_lost));
}

struct MeshScore {
  std::string robot_ns;  // whose map: a robot's namespace, or "station" (a centralized mapper)
  std::string from;      // robot_ns, or "robot_ns/component" where one place has two mappers
  std::string mesh_path, octomap_path;
  double voxel_m = 0;
  double e_max_m = 0;  // the evaluation's
  std::optional<eval::ReconstructionError> error;
  double coverage_reachable = NAN;  // of the points the team can observe
};

// The voxel size of an OctoMap binary file (its text header's "res" line); 0 if unreadable.
double octomap_resolution(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int i = 0; i < 8 && std::getline(in, line); ++i)
    if (line.rfind("res ", 0) == 0) return std::atof(line.c_str() + 4);
  return 0;
}

// The meshes other processes of the team wrote into the run directory since `since` (a
// simulator process has no mapper: its robots' processes write mesh_<ns>.ply there).
std::vector<MeshScore> meshes_in(const fs::path& dir, fs::file_time_type since) {
  std::vector<MeshScore> scores;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("mesh_", 0) != 0 || entry.path().extension() != ".ply") continue;
    if (entry.last_write_time(ec) < since) continue;
    MeshScore s;
    s.robot_ns = name.substr(5, name.size() - 9);
    s.from = s.robot_ns;
    s.mesh_path = entry.path().string();
    const fs::path map = dir / ("map_" + s.robot_ns + ".bt");
    if (fs::exists(map, ec)) {
      s.octomap_path = map.string();
      s.voxel_m = octomap_resolution(map);
    }
    if (s.voxel_m <= 0) {
      std::fprintf(stderr,
                   "scancrew run: %s: no map_%s.bt beside it to give its voxel size; "
                   "not scored\n",
                   s.mesh_path.c_str(), s.robot_ns.c_str());
      continue;
    }
    scores.push_back(std::move(s));
  }
  std::sort(scores.begin(), scores.end(),
            [](const MeshScore& a, const MeshScore& b) { return a.robot_ns < b.robot_ns; });
  return scores;
}

// Each mapper's mesh (written as the launch stopped) against the scene's ground truth.
std::vector<MeshScore> score_meshes(const Launch& launch, const MissionMonitor& monitor,
                                    fs::file_time_type started) {
  std::vector<MeshScore> scores;
  std::vector<std::string> component_names;
  for (const auto& c : launch.components()) {
    const auto* mapper = dynamic_cast<const tsdf::TsdfMapper*>(c.get());
    if (mapper == nullptr) continue;
    MeshScore s;
    // a centralized mapper is the ground station's; the others are a robot's
    s.robot_ns = "station";
    if (mapper->config().mode != "centralized")
      for (const auto& r : monitor.robots())
        if (r.id == mapper->robot_id()) s.robot_ns = r.ns;
    s.mesh_path = mapper->config().mesh_path;
    s.octomap_path = mapper->config().octomap_path;
    s.voxel_m = mapper->config().tsdf.voxel_m;
    const std::string& name = mapper->qualified_name();
    component_names.push_back(name.substr(name.rfind('/') + 1));
    scores.push_back(std::move(s));
  }
  // two mappers of one place (a planning map and a finer reconstruction map) go by
  // "place/component"
  std::map<std::string, int> per_place;
  for (const MeshScore& s : scores) ++per_place[s.robot_ns];
  for (size_t i = 0; i < scores.size(); ++i)
    scores[i].from = scores[i].robot_ns +
                     (per_place[scores[i].robot_ns] > 1 ? "/" + component_names[i] : std::string());
  if (scores.empty()) scores = meshes_in(launch.out_dir(), started);
  const std::string& scene_path = monitor.config().scene;
  if (scene_path.empty()) return scores;
  auto scene = sim::load_scene(scene_path);
  if (!scene) return scores;
  auto meshes = sim::load_scene_meshes(*scene);
  if (!meshes) return scores;
  const auto truth = sim::sample_surfaces(*scene, *meshes,
                                          {.density_per_m2 = monitor.config().eval_density_per_m2,
                                           .seed = 1,
                                           .visibility_rays = monitor.config().visibility_rays});
  if (!truth) {
    std::fprintf(stderr, "scancrew run: evaluation: %s\n",
                 scancrew::log::printable(truth.error()).c_str());
    return scores;
  }
  // the points the team's robot kinds can observe from their starts (docs/evaluation.md)
  auto observable =
      eval::team_observable(*scene, *meshes, truth->points, truth->normals, monitor.team_starts());
  if (!observable)
    std::fprintf(stderr, "scancrew run: evaluation: reachable ground truth: %s\n",
                 scancrew::log::printable(observable.error()).c_str());
  for (MeshScore& s : scores) {
    if (s.mesh_path.empty()) continue;
    const auto mesh = eval::read_ply_mesh(s.mesh_path);
    if (!mesh) {
      std::fprintf(stderr, "scancrew run: evaluation: %s\n",
                   scancrew::log::printable(mesh.error()).c_str());
      continue;
    }
    s.e_max_m = monitor.config().eval_e_max_m > 0 ? monitor.config().eval_e_max_m
                                                  : eval::max_error_for_voxel(s.voxel_m);
    auto r = eval::reconstruction_error(*mesh, truth->points, truth->normals,
                                        {.e_max_m = s.e_max_m, .per_point_error = true});
    if (r && observable) {
      std::vector<uint8_t> covered(r->point_error_m.size());
      for (size_t i = 0; i < covered.size(); ++i)
        covered[i] = std::isnan(r->point_error_m[i]) ? 0 : 1;
      const double share = eval::share_of_observable(*observable, covered);
      s.coverage_reachable = share >= 0 ? share : NAN;
      r->point_error_m = {};  // 4 bytes a point: not kept
    }
    if (r)
      s.error = std::move(r).value();
    else
      std::fprintf(stderr, "scancrew run: evaluation of %s: %s\n", s.mesh_path.c_str(),
                   scancrew::log::printable(r.error()).c_str());
  }
  return scores;
}

// x per goal reached; null without a goal reached.
Json per_goal(double x, uint64_t goals) {
  return goals > 0 ? Json(x / static_cast<double>(goals)) : Json(nullptr);
}

// Where the team's time went and how fast it covered the scene (docs/missions.md, "Where the
// time goes"): the mean share of each activity over the robots, plan churn (tours per goal
// reached), metres per goal, coverage per metre and per minute, the times to 50 / 90 / 95 %
// coverage (the monitor's estimate), and what each place computed.
void add_exploration_metrics(Json& m, const Launch& launch, const MissionMonitor& monitor,
                             const std::map<uint32_t, const low_level::LowLevelPlanner*>& planners,
                             double sim_s) {
  const auto robots = monitor.robots();
  Json share = Json::object();
  for (size_t a = 0; a < mission::kActivityCount; ++a) {
    double sum = 0;
    for (const auto& r : robots) sum += r.time.total() > 0 ? r.time.seconds[a] / r.time.total() : 0;
    share[std::string(mission::to_string(static_cast<mission::Activity>(a)))] =
        robots.empty() ? 0.0 : sum / static_cast<double>(robots.size());
  }
  m["idle_share"] = share["idle_open"].get<double>() + share["idle_done"].get<double>();
  m["time_share"] = std::move(share);
  uint64_t tours = 0, goals = 0;
  for (const auto& [id, p] : planners) {
    tours += p->stats().tours;
    goals += p->stats().goals_reached;
  }
  double path_m = 0;
  for (const auto& r : robots) path_m += r.path_length_m;
  m["goals_reached"] = goals;
  m["tours_per_goal"] = per_goal(static_cast<double>(tours), goals);
  m["m_per_goal"] = per_goal(path_m, goals);
  const double coverage = m["coverage"].is_number() ? m["coverage"].get<double>() : NAN;
  m["coverage_per_m"] = number_or_null(path_m > 0 ? coverage / path_m : NAN);
  m["coverage_per_min"] = number_or_null(sim_s > 0 ? coverage / (sim_s / 60.0) : NAN);
  const auto samples = monitor.coverage();
  for (const bool reachable : {false, true}) {
    Json times = Json::object();
    for (const double share_of : {0.5, 0.9, 0.95}) {
      const auto t = mission::time_to_coverage(samples, share_of, reachable);
      times[std::to_string(std::lround(100 * share_of))] = t ? Json(*t) : Json(nullptr);
    }
    m[reachable ? "time_to_coverage_reachable_s" : "time_to_coverage_s"] = std::move(times);
  }
  m["compute_time"] = std::string(to_string(launch.settings().compute_time));
  m["compute_scale"] = launch.settings().charge.scale;
  m["place_cores"] = launch.settings().charge.cores;
  Json places = Json::array();
  for (const PlaceStats& p : launch.place_stats())
    places.push_back({{"place", p.name},
                      {"callbacks", p.callbacks},
                      {"busy_s", p.charged_s},
                      {"busy_share", number_or_null(sim_s > 0 ? p.charged_s / sim_s : NAN)},
                      {"max_callback_ms", p.max_callback_ms}});
  m["places"] = std::move(places);
}

bool copy_into(const std::string& from, const fs::path& to) {
  std::error_code ec;
  if (from.empty() || !fs::exists(from, ec)) return false;
  if (fs::exists(to, ec) && fs::equivalent(from, to, ec)) return true;
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  if (ec)
    std::fprintf(stderr, "scancrew run: copying %s: %s\n", from.c_str(), ec.message().c_str());
  return !ec;
}

struct RunFacts {
  std::string launch_path, started, stop_reason;
  fs::file_time_type started_at;
  double sim_s = 0, wall_s = 0;
};

// Writes the run directory; returns false (after saying why) if a file could not be written.
bool write_run_directory(const Launch& launch, const MissionMonitor& monitor, const RunFacts& run,
                         const fs::path& out) {
  bool ok = true;
  auto check = [&](const Result<void, std::string>& r) {
    if (!r) {
      std::fprintf(stderr, "scancrew run: %s\n", scancrew::log::printable(r.error()).c_str());
      ok = false;
    }
  };
  check(mission::write_paths_csv((out / "paths.csv").string(), monitor.paths()));
  check(mission::write_coverage_csv((out / "coverage.csv").string(), monitor.coverage()));

  const auto scores = score_meshes(launch, monitor, run.started_at);
  // a place with two mappers is represented by its finer one (the reconstruction map), so
  // the choice does not hang on comparing coverages scored at two e_max
  const auto represents_place = [&](const MeshScore& s) {
    return std::none_of(scores.begin(), scores.end(), [&](const MeshScore& o) {
      return o.robot_ns == s.robot_ns && o.voxel_m < s.voxel_m;
    });
  };
  const MeshScore* best = nullptr;
  for (const MeshScore& s : scores)
    if (s.error && represents_place(s) &&
        (best == nullptr || s.error->coverage > best->error->coverage))
      best = &s;
  if (best == nullptr)
    for (const MeshScore& s : scores)
      if (!s.mesh_path.empty() && represents_place(s) && best == nullptr) best = &s;
  if (best != nullptr) {
    copy_into(best->mesh_path, out / "mesh.ply");
    // a reconstruction-only mapper writes no OctoMap: its place's planning map's then
    const MeshScore* map_from = best;
    for (const MeshScore& s : scores)
      if (map_from->octomap_path.empty() && !s.octomap_path.empty() && s.robot_ns == best->robot_ns)
        map_from = &s;
    copy_into(map_from->octomap_path, out / "map.bt");
  }

  Json m;
  m["launch"] = run.launch_path;
  m["scene"] = monitor.config().scene;
  std::string architecture = "single";
  uint64_t bytes = 0;
  for (const auto& c : launch.components())
    if (const auto* mapper = dynamic_cast<const tsdf::TsdfMapper*>(c.get())) {
      architecture = mapper->config().mode;
      bytes += mapper->stats().patch_wire_bytes;
    }
  m["architecture"] = architecture;
  m["started"] = run.started;
  m["completed"] = run.stop_reason == "complete";
  m["stop_reason"] = run.stop_reason;
  const auto completion = monitor.completion_time_s();
  m["completion_time_s"] = completion ? Json(*completion) : Json(nullptr);
  m["sim_time_s"] = run.sim_s;
  m["wall_time_s"] = run.wall_s;
  m["real_time_factor"] = number_or_null(run.wall_s > 0 ? run.sim_s / run.wall_s : NAN);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const eval::ReconstructionError* e = best && best->error ? &*best->error : nullptr;
  m["mesh_from"] = best ? Json(best->from) : Json(nullptr);
  m["coverage"] = number_or_null(e ? e->coverage : nan);
  m["coverage_reachable"] = number_or_null(e ? best->coverage_reachable : nan);
  m["mean_error_m"] = number_or_null(e ? e->mean_error_m : nan);
  m["std_error_m"] = number_or_null(e ? e->std_error_m : nan);
  m["rmse_m"] = number_or_null(e ? e->rmse_m : nan);
  m["eval_density_per_m2"] = monitor.config().eval_density_per_m2;
  m["eval_e_max_m"] = number_or_null(e ? best->e_max_m : nan);
  Json meshes = Json::array();
  for (const MeshScore& s : scores) {
    const eval::ReconstructionError* se = s.error ? &*s.error : nullptr;
    meshes.push_back({{"from", s.from},
                      {"mesh", s.mesh_path},
                      {"voxel_m", s.voxel_m},
                      {"e_max_m", number_or_null(se ? s.e_max_m : nan)},
                      {"coverage", number_or_null(se ? se->coverage : nan)},
                      {"coverage_reachable", number_or_null(se ? s.coverage_reachable : nan)},
                      {"rmse_m", number_or_null(se ? se->rmse_m : nan)}});
  }
  m["meshes"] = std::move(meshes);
  m["eval_visibility_rays"] = monitor.config().visibility_rays;

  std::map<uint32_t, const low_level::LowLevelPlanner*> planners;
  uint64_t robot_robot = 0, robot_scene = 0;
  for (const auto& c : launch.components()) {
    if (const auto* p = dynamic_cast<const low_level::LowLevelPlanner*>(c.get()))
      planners[p->robot_id()] = p;
    if (const auto* s = dynamic_cast<const components::TeamSimulator*>(c.get());
        s && s->simulator()) {
      robot_robot += s->simulator()->contacts().robot_robot;
      robot_scene += s->simulator()->contacts().robot_scene;
    }
  }
  double total_length = 0;
  uint64_t replans = 0;
  Json robots = Json::array();
  for (const auto& r : monitor.robots()) {
    Json j;
    j["id"] = r.id;
    j["namespace"] = r.ns;
    j["kind"] = r.kind;
    j["path_length_m"] = r.path_length_m;
    total_length += r.path_length_m;
    const auto p = planners.find(r.id);
    const uint64_t robot_replans =
        p != planners.end() ? p->second->stats().replans : r.planning_requests;
    replans += robot_replans;
    j["replans"] = robot_replans;
    // the score of the robot's (finest) map's mesh, else the monitor's estimate
    double coverage = r.coverage >= 0 ? r.coverage : nan;
    for (const MeshScore& s : scores)
      if (s.robot_ns == r.ns && s.error && represents_place(s)) coverage = s.error->coverage;
    j["coverage"] = number_or_null(coverage);
    if (p != planners.end()) {
      const auto& st = p->second->stats();
      j["goals_reached"] = st.goals_reached;
      j["tours"] = st.tours;
      j["tours_per_goal"] = per_goal(static_cast<double>(st.tours), st.goals_reached);
      j["m_per_goal"] = per_goal(r.path_length_m, st.goals_reached);
    }
    Json time = Json::object();
    for (size_t a = 0; a < mission::kActivityCount; ++a)
      time[std::string(mission::to_string(static_cast<mission::Activity>(a)))] = r.time.seconds[a];
    j["time_s"] = std::move(time);
    j["ises_left"] = r.ises_left;
    j["state"] = r.have_state ? std::string(msg::to_string(r.mode)) : "starting";
    robots.push_back(std::move(j));
  }
  m["total_path_length_m"] = total_length;
  add_exploration_metrics(m, launch, monitor, planners, run.sim_s);
  // distributed: the completed patches the robots sent (their wire size). Centralized: the
  // depth images and poses to the station, which an in-process run does not serialise, so
  // not measured here (null), rather than a 0 that would read as "nothing sent".
  m["data_exchanged_bytes"] = architecture == "centralized" ? Json(nullptr) : Json(bytes);
  m["collisions"] = robot_robot + robot_scene;
  m["contacts"] = {{"robot_robot", robot_robot}, {"robot_scene", robot_scene}};
  m["replans"] = replans;
  m["robots"] = std::move(robots);
  if (const Tracer* tracer = launch.tracer()) {
    Json times = Json::object();
    for (const ComponentTime& t : tracer->component_times())
      times[t.component] = {{"callbacks", t.callbacks},
                            {"total_ms", t.total_ms},
                            {"p50_ms", t.p50_ms},
                            {"p99_ms", t.p99_ms}};
    m["compute_ms"] = std::move(times);
    check(tracer->write_chrome_trace((out / "trace.json").string()));
    if (tracer->dropped_events() > 0)
      std::fprintf(stderr,
                   "scancrew run: trace.json holds the first %zu callbacks; %llu more were only "
                   "counted (--trace-events)\n",
                   static_cast<size_t>(tracer->event_count()),
                   static_cast<unsigned long long>(tracer->dropped_events()));
  }

  std::ofstream file(out / "metrics.json");
  file << m.dump(2) << "\n";
  if (!file) {
    std::fprintf(stderr, "scancrew run: cannot write %s\n", (out / "metrics.json").c_str());
    return false;
  }
  file.close();
  check(mission::write_report(out.string()));

  const char* how = run.stop_reason == "complete"      ? "complete"
                    : run.stop_reason == "stalled"     ? "stalled"
                    : run.stop_reason == "interrupted" ? "interrupted"
                                                       : "out of time";
  std::printf("mission %s after %.1f s simulated (%.1f s wall)", how, run.sim_s, run.wall_s);
  if (e) std::printf("; coverage %.2f %% (map of %s)", 100 * e->coverage, best->from.c_str());
  if (e && std::isfinite(best->coverage_reachable))
    std::printf(", %.2f %% of the reachable surface", 100 * best->coverage_reachable);
  std::printf("; contacts robot-scene %llu robot-robot %llu\n",
              static_cast<unsigned long long>(robot_scene),
              static_cast<unsigned long long>(robot_robot));
  std::printf("run directory %s: report %s\n", out.c_str(), (out / "report.html").c_str());
  return ok;
}

}  // namespace

// What the components reported failed during the run (Component::report_failure), listed;
// false when nothing did.
bool print_failures(Launch& launch) {
  const auto failures = launch.graph().failures();
  if (failures.empty()) return false;
  std::fprintf(stderr, "scancrew run: %zu failure(s) during the run lost data or output:\n",
               failures.size());
  for (const auto& f : failures)
    std::fprintf(stderr, "  %s\n", scancrew::log::printable(f).c_str());
  return true;
}

int run_launch(const RunOptions& o) {
  const auto text = launch_file_text(o.launch_path, o.robot_count);
  if (!text) {
    std::fprintf(stderr, "scancrew: %s; nothing was started\n",
                 scancrew::log::printable(text.error()).c_str());
    return 2;
  }
  auto composed = Launch::from_string(*text, o.launch_path,
                                      {.overrides = o.sets,
                                       .out_dir = o.out_dir,
                                       .robot_count = o.robot_count,
                                       .process = o.process,
                                       .robot_id = o.robot_id});
  if (!composed) {
    std::fprintf(stderr, "scancrew: %s: %zu error(s); nothing was started\n", o.launch_path.c_str(),
                 composed.error().size());
    for (const auto& e : composed.error())
      std::fprintf(stderr, "  %s\n", scancrew::log::printable(e).c_str());
    return 2;
  }
  auto launch = std::move(composed).value();
  MissionMonitor* monitor = launch->find_component<MissionMonitor>();
  // a mission whose robot or station has an input nothing feeds would run blind (a mapper
  // reading a depth topic nobody publishes completed at once): refused, as a bad launch file
  // is. The world's components (the monitor, a replay) only watch: a warning for them. One
  // process of a team split over processes gets its other inputs over DDS: not checked.
  const GraphReport graph_report = launch->report();
  std::vector<std::string> unconnected;
  for (const EndpointInfo& e : graph_report.unconnected_inputs)
    if (monitor != nullptr && o.process == "run" && !launch->is_world(e.component))
      unconnected.push_back("unconnected input: " + e.component + "." + e.port + " reads '" +
                            e.topic + "' (" + e.type_name + ") but nothing publishes it");
  for (const auto& w : graph_report.warnings)
    if (std::find(unconnected.begin(), unconnected.end(), w) == unconnected.end())
      std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!unconnected.empty()) {
    std::fprintf(stderr,
                 "scancrew: %s: %zu error(s): a mission's components must have every input "
                 "connected; nothing was started\n",
                 o.launch_path.c_str(), unconnected.size());
    for (const auto& e : unconnected)
      std::fprintf(stderr, "  %s\n", scancrew::log::printable(e).c_str());
    return 2;
  }
  const fs::path out = launch->out_dir();
  if (monitor != nullptr) {
    // one process of a split team sees no maps of the others: it cannot tell
    monitor->set_depth_required(o.process == "run");
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) {
      std::fprintf(stderr, "scancrew run: cannot create the run directory %s: %s\n", out.c_str(),
                   ec.message().c_str());
      return 1;
    }
    launch->set_stop_condition([monitor] { return monitor->finished(); });
    if (o.trace_events > 0) launch->enable_tracing(o.trace_events);
  }
  // one process of a team: its bridge's lockstep paces the steps (docs/processes.md)
  std::vector<const dds_bridge::DdsBridge*> bridges;
  for (const auto& c : launch->components())
    if (auto* bridge = dynamic_cast<dds_bridge::DdsBridge*>(c.get())) {
      bridges.push_back(bridge);
      if (StepGate* gate = bridge->step_gate()) {
        if (launch->settings().executor != LaunchSettings::ExecutorType::kStep) {
          std::fprintf(stderr,
                       "scancrew: %s: %s: lockstep needs executor: {type: step} (sim time)\n",
                       o.launch_path.c_str(), bridge->qualified_name().c_str());
          return 2;
        }
        launch->set_step_gate(gate);
      }
    }
  RunFacts run{.launch_path = o.launch_path,
               .started = local_time_now(),
               .started_at = fs::file_time_type::clock::now()};
  g_running = launch.get();
  g_interrupted = 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::fprintf(stderr, "scancrew: running %s (%zu components; Ctrl-C stops%s)\n",
               o.launch_path.c_str(), launch->components().size(),
               monitor ? ", results are still written" : "");
  const auto wall_start = std::chrono::steady_clock::now();
  const auto wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  run.sim_s = launch->run([&](double elapsed, double duration) {
    if (monitor)
      print_mission_progress(*monitor, elapsed, duration, wall(), false);
    else
      print_progress(stderr, launch->graph(), elapsed, duration, false);
  });
  run.wall_s = wall();
  const bool interrupted = g_interrupted != 0;  // Ctrl-C / SIGTERM, not the monitor's stop
  g_running = nullptr;
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  std::fprintf(stderr, "\n");
  for (const auto* bridge : bridges) print_bridge_bytes(*bridge, run.sim_s);
  if (monitor == nullptr) {
    print_topic_stats(stdout, launch->graph());
    return print_failures(*launch) ? 4 : 0;  // docs/missions.md, "Exit status"
  }
  print_mission_progress(*monitor, run.sim_s, launch->settings().duration_s, run.wall_s, true);
  monitor->close_time_breakdown();
  run.stop_reason = monitor->finished() ? monitor->stop_reason()
                    : interrupted       ? "interrupted"
                                        : "time_budget";
  // the per-topic table goes to the run directory; the terminal gets the summary
  if (std::FILE* f = std::fopen((out / "topics.txt").c_str(), "w"); f != nullptr) {
    print_topic_stats(f, launch->graph());
    std::fclose(f);
  }
  if (!write_run_directory(*launch, *monitor, run, out)) return 1;
  // a robot whose depth never reached a map saw nothing: the graph is miswired
  if (const auto blind = monitor->robots_without_depth(); !blind.empty()) {
    std::string names;
    for (const auto& n : blind) names += (names.empty() ? "" : ", ") + n;
    std::fprintf(stderr,
                 "scancrew run: %s: configuration error: no map integrated a depth image of %s "
                 "(is the mapper's depth_topic published for that robot? scancrew graph %s)\n",
                 o.launch_path.c_str(), names.c_str(), o.launch_path.c_str());
    return 2;
  }
  // docs/missions.md, "Exit status"
  if (print_failures(*launch)) return 4;
  if (run.stop_reason == "complete") return 0;
  return interrupted ? 130 : 3;
}

}  // namespace scancrew::cli
