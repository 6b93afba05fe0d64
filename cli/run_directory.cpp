#include "cli/run_directory.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "cli/mesh_scores.hpp"
#include "cli/run_record.hpp"
#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "executors/log.hpp"
#include "executors/trace.hpp"
#include "report/run_files.hpp"
#include "report/run_report.hpp"
#include "report/time_breakdown.hpp"

namespace scancrew::cli {

namespace {

namespace fs = std::filesystem;
using mission_monitor::MissionMonitor;
using Json = nlohmann::ordered_json;
using Planners = std::map<uint32_t, RunSummary::Planner>;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// NaN and infinities have no JSON form: null.
Json number_or_null(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
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
                             const Planners& planners, double sim_s) {
  const auto robots = monitor.robots();
  Json share = Json::object();
  for (size_t a = 0; a < report::kActivityCount; ++a) {
    double sum = 0;
    for (const auto& r : robots) sum += r.time.total() > 0 ? r.time.seconds[a] / r.time.total() : 0;
    share[std::string(report::to_string(static_cast<report::Activity>(a)))] =
        robots.empty() ? 0.0 : sum / static_cast<double>(robots.size());
  }
  m["idle_share"] = share["idle_open"].get<double>() + share["idle_done"].get<double>();
  m["time_share"] = std::move(share);
  uint64_t tours = 0, goals = 0;
  for (const auto& [id, p] : planners) {
    tours += p.tours;
    goals += p.goals_reached;
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
      const auto t = report::time_to_coverage(samples, share_of, reachable);
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

// The mesh the run is judged by, copied to mesh.ply, with its place's map as map.bt (a
// reconstruction-only mapper writes no OctoMap: its place's planning map's then).
void copy_best_mesh(const std::vector<MeshScore>& scores, const MeshScore* best,
                    const fs::path& out) {
  if (best == nullptr) return;
  copy_into(best->mesh_path, out / "mesh.ply");
  const MeshScore* map_from = best;
  for (const MeshScore& s : scores)
    if (map_from->octomap_path.empty() && !s.octomap_path.empty() && s.robot_ns == best->robot_ns)
      map_from = &s;
  copy_into(map_from->octomap_path, out / "map.bt");
}

// The architecture (the mappers' mode) and the patches' wire bytes the mappers sent.
struct Exchange {
  std::string architecture{name_of(tsdf_mapper::kMapModeNames, tsdf_mapper::MapMode::kSingle)};
  uint64_t patch_bytes = 0;
};
Exchange exchange_of(const RunSummary& summary) {
  Exchange x;
  for (const RunSummary::Map& map : summary.maps) {
    x.architecture = map.mode;
    x.patch_bytes += map.patch_wire_bytes;
  }
  return x;
}

// The run's facts and the scores of its meshes: the top of metrics.json.
Json run_metrics(const MissionMonitor& monitor, const RunFacts& run,
                 const std::string& architecture, const std::vector<MeshScore>& scores,
                 const MeshScore* best) {
  Json m;
  m["launch"] = run.launch_path;
  m["scene"] = monitor.config().scene;
  m["architecture"] = architecture;
  m["started"] = run.started;
  m["command"] = shell_quoted(command_line());  // as run.json has it, for the report
  m["completed"] = run.stop_reason == StopReason::kComplete;
  m["stop_reason"] = to_string(run.stop_reason);
  const auto completion = monitor.completion_time_s();
  m["completion_time_s"] = completion ? Json(*completion) : Json(nullptr);
  m["sim_time_s"] = run.sim_s;
  m["wall_time_s"] = run.wall_s;
  m["real_time_factor"] = number_or_null(run.wall_s > 0 ? run.sim_s / run.wall_s : kNan);
  const eval::ReconstructionError* e = best && best->error ? &*best->error : nullptr;
  m["mesh_from"] = best ? Json(best->from) : Json(nullptr);
  m["coverage"] = number_or_null(e ? e->coverage : kNan);
  m["coverage_reachable"] = number_or_null(e ? best->coverage_reachable : kNan);
  m["mean_error_m"] = number_or_null(e ? e->mean_error_m : kNan);
  m["std_error_m"] = number_or_null(e ? e->std_error_m : kNan);
  m["rmse_m"] = number_or_null(e ? e->rmse_m : kNan);
  m["eval_density_per_m2"] = monitor.config().eval_density_per_m2;
  m["eval_e_max_m"] = number_or_null(e ? best->e_max_m : kNan);
  Json meshes = Json::array();
  for (const MeshScore& s : scores) {
    const eval::ReconstructionError* se = s.error ? &*s.error : nullptr;
    meshes.push_back({{"from", s.from},
                      {"mesh", s.mesh_path},
                      {"voxel_m", s.voxel_m},
                      {"e_max_m", number_or_null(se ? s.e_max_m : kNan)},
                      {"coverage", number_or_null(se ? se->coverage : kNan)},
                      {"coverage_reachable", number_or_null(se ? s.coverage_reachable : kNan)},
                      {"rmse_m", number_or_null(se ? se->rmse_m : kNan)}});
  }
  m["meshes"] = std::move(meshes);
  m["eval_visibility_rays"] = monitor.config().visibility_rays;
  return m;
}

// One robot's entry of metrics.json: path, replans, coverage (the score of its finest map's
// mesh, else the monitor's estimate), goals, tours and where its time went.
// A robot's odometry (vio) in metrics.json: frames, losses (by reason) and losses per 100 m of
// its path, the measure of Step 14's target.
Json odometry_metrics(const RunSummary::Odometry& o, double path_length_m) {
  Json j;
  j["frames"] = o.frames;
  j["losses"] = o.losses;
  j["coasted_frames"] = o.coasted_frames;
  j["losses_per_100m"] = path_length_m > 0
                             ? Json(100.0 * static_cast<double>(o.losses) / path_length_m)
                             : Json(nullptr);
  Json reasons = Json::object();
  for (const auto& [reason, n] : o.losses_by_reason) reasons[reason] = n;
  j["losses_by_reason"] = std::move(reasons);
  j["mean_frame_ms"] = o.mean_frame_ms;
  j["max_frame_ms"] = o.max_frame_ms;
  if (o.scored_poses > 0) {  // against the simulator's truth (mission_monitor/pose_error.hpp)
    j["scored_poses"] = o.scored_poses;
    j["ate_rmse_m"] = o.ate_rmse_m;
    j["ate_max_m"] = o.ate_max_m;
    j["ate_percent_of_distance"] =
        o.truth_distance_m > 0 ? Json(100.0 * o.ate_rmse_m / o.truth_distance_m) : Json(nullptr);
    j["rpe_mean_percent"] = o.rpe_mean_percent;
  }
  return j;
}

Json robot_metrics(const MissionMonitor::RobotProgress& r, const RunSummary& summary,
                   const std::vector<MeshScore>& scores) {
  const Planners& planners = summary.planners;
  Json j;
  j["id"] = r.id;
  j["namespace"] = r.ns;
  j["kind"] = robot::to_string(r.kind);
  j["path_length_m"] = r.path_length_m;
  const auto p = planners.find(r.id);
  j["replans"] = p != planners.end() ? p->second.replans : r.planning_requests;
  double coverage = r.coverage >= 0 ? r.coverage : kNan;
  for (const MeshScore& s : scores)
    if (s.robot_ns == r.ns && s.error && represents_place(scores, s)) coverage = s.error->coverage;
  j["coverage"] = number_or_null(coverage);
  if (p != planners.end()) {
    const RunSummary::Planner& st = p->second;
    j["goals_reached"] = st.goals_reached;
    j["tours"] = st.tours;
    j["tours_per_goal"] = per_goal(static_cast<double>(st.tours), st.goals_reached);
    j["m_per_goal"] = per_goal(r.path_length_m, st.goals_reached);
  }
  Json time = Json::object();
  for (size_t a = 0; a < report::kActivityCount; ++a)
    time[std::string(report::to_string(static_cast<report::Activity>(a)))] = r.time.seconds[a];
  j["time_s"] = std::move(time);
  j["ises_left"] = r.ises_left;
  for (const RunSummary::Map& map : summary.maps)  // distributed: the map patches it sent
    if (map.robot_id == r.id &&
        map.mode == name_of(tsdf_mapper::kMapModeNames, tsdf_mapper::MapMode::kDistributed))
      j["patch_bytes_sent"] = map.patch_wire_bytes;
  j["state"] = r.have_state ? std::string(msg::to_string(r.mode)) : "starting";
  if (const auto o = summary.odometry.find(r.id); o != summary.odometry.end())
    j["odometry"] = odometry_metrics(o->second, r.path_length_m);
  if (const auto l = summary.command_latency.find(r.id); l != summary.command_latency.end())
    j["command_latency"] = {{"commands", l->second.commands},
                            {"poses", l->second.poses},
                            {"age_ms",
                             {{"p50", l->second.age_p50_ms},
                              {"p99", l->second.age_p99_ms},
                              {"max", l->second.age_max_ms}}},
                            {"first_use_ms",
                             {{"p50", l->second.first_use_p50_ms},
                              {"p99", l->second.first_use_p99_ms},
                              {"max", l->second.first_use_max_ms}}}};
  return j;
}

// Per-component compute times into m, and trace.json; false if it could not be written.
bool add_trace(Json& m, const Tracer& tracer, const fs::path& out) {
  Json times = Json::object();
  for (const ComponentTime& t : tracer.component_times())
    times[t.component] = {{"callbacks", t.callbacks},
                          {"total_ms", t.total_ms},
                          {"p50_ms", t.p50_ms},
                          {"p99_ms", t.p99_ms}};
  m["compute_ms"] = std::move(times);
  const auto written = tracer.write_chrome_trace((out / "trace.json").string());
  if (!written)
    std::fprintf(stderr, "scancrew run: %s\n", scancrew::log::printable(written.error()).c_str());
  if (tracer.dropped_events() > 0)
    std::fprintf(stderr,
                 "scancrew run: trace.json holds the first %zu callbacks; %llu more were only "
                 "counted (--trace-events)\n",
                 static_cast<size_t>(tracer.event_count()),
                 static_cast<unsigned long long>(tracer.dropped_events()));
  return static_cast<bool>(written);
}

// How the summary line says a mission ended.
std::string ending_of(StopReason reason) {
  switch (reason) {
    case StopReason::kComplete:
    case StopReason::kStalled:
    case StopReason::kInterrupted:
      return to_string(reason);
    case StopReason::kTimeBudget:
    case StopReason::kFailed:
      break;
  }
  return "out of time";
}

// The line `scancrew run` ends with: how the mission ended, its coverage and contacts.
void print_summary(const RunFacts& run, const MeshScore* best, const RunSummary::Contacts& contacts,
                   const fs::path& out) {
  std::printf("mission %s after %.1f s simulated (%.1f s wall)", ending_of(run.stop_reason).c_str(),
              run.sim_s, run.wall_s);
  const eval::ReconstructionError* e = best && best->error ? &*best->error : nullptr;
  if (e) std::printf("; coverage %.2f %% (map of %s)", 100 * e->coverage, best->from.c_str());
  if (e && std::isfinite(best->coverage_reachable))
    std::printf(", %.2f %% of the reachable surface", 100 * best->coverage_reachable);
  std::printf("; contacts robot-scene %llu robot-robot %llu\n",
              static_cast<unsigned long long>(contacts.robot_scene),
              static_cast<unsigned long long>(contacts.robot_robot));
  std::printf("run directory %s: report %s\n", out.c_str(), (out / "report.html").c_str());
}

}  // namespace

bool write_run_directory(const Launch& launch, const MissionMonitor& monitor, const RunFacts& run,
                         const fs::path& out) {
  bool ok = true;
  auto check = [&](const Result<void, std::string>& r) {
    if (!r) {
      std::fprintf(stderr, "scancrew run: %s\n", scancrew::log::printable(r.error()).c_str());
      ok = false;
    }
  };
  check(report::write_paths_csv((out / "paths.csv").string(), monitor.paths()));
  check(report::write_coverage_csv((out / "coverage.csv").string(), monitor.coverage()));
  const RunSummary summary = launch.summary();
  const auto scores = score_meshes(launch, monitor, run.started_at);
  const MeshScore* best = best_mesh(scores);
  copy_best_mesh(scores, best, out);

  const Exchange exchange = exchange_of(summary);
  Json m = run_metrics(monitor, run, exchange.architecture, scores, best);
  const Planners& planners = summary.planners;
  const RunSummary::Contacts& contacts = summary.contacts;
  double total_length = 0;
  uint64_t replans = 0;
  Json robots = Json::array();
  for (const auto& r : monitor.robots()) {
    robots.push_back(robot_metrics(r, summary, scores));
    total_length += r.path_length_m;
    replans += robots.back()["replans"].get<uint64_t>();
  }
  m["total_path_length_m"] = total_length;
  add_exploration_metrics(m, launch, monitor, planners, run.sim_s);
  // distributed: the completed patches the robots sent (their wire size). Centralized: the
  // depth images and poses to the station, which an in-process run does not serialise, so
  // not measured here (null), rather than a 0 that would read as "nothing sent".
  m["data_exchanged_bytes"] = exchange.architecture == name_of(tsdf_mapper::kMapModeNames,
                                                               tsdf_mapper::MapMode::kCentralized)
                                  ? Json(nullptr)
                                  : Json(exchange.patch_bytes);
  m["collisions"] = contacts.robot_robot + contacts.robot_scene;
  m["contacts"] = {{"robot_robot", contacts.robot_robot}, {"robot_scene", contacts.robot_scene}};
  m["replans"] = replans;
  m["robots"] = std::move(robots);
  if (!summary.frame_misalignment.empty()) {  // robots on an odometry (pose_error.hpp)
    Json pairs = Json::array();
    for (const RunSummary::FrameMisalignment& f : summary.frame_misalignment)
      pairs.push_back({{"robots", {f.robot_a, f.robot_b}},
                       {"samples", f.samples},
                       {"mean_m", f.mean_m},
                       {"max_m", f.max_m},
                       {"last_m", f.last_m},
                       {"max_yaw_deg", f.max_yaw_deg}});
    m["frame_misalignment"] = std::move(pairs);
  }
  if (const auto& w = summary.wall_clock_sim)
    m["wall_clock"] = {{"simulated_s", w->simulated_s},
                       {"ticks", w->ticks},
                       {"late_ticks", w->late_ticks},
                       {"capped_ticks", w->capped_ticks},
                       {"max_lag_s", w->max_lag_s}};
  if (const Tracer* tracer = launch.tracer()) ok = add_trace(m, *tracer, out) && ok;

  std::ofstream file(out / "metrics.json");
  file << m.dump(2) << "\n";
  if (!file) {
    std::fprintf(stderr, "scancrew run: cannot write %s\n", (out / "metrics.json").c_str());
    return false;
  }
  file.close();
  check(report::write_report(out.string()));
  print_summary(run, best, contacts, out);
  return ok;
}

}  // namespace scancrew::cli
