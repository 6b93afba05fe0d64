#include "components/mission_monitor/mission_monitor.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"
#include "sim/robot_model.hpp"

namespace scancrew::mission_monitor {

namespace {

using Mode = msg::RobotState::Mode;

double yaw_of(const msg::Pose3& pose) {
  const Eigen::Matrix3d rotation = msg::to_eigen(pose).linear();
  return std::atan2(rotation(1, 0), rotation(0, 0));
}

}  // namespace

MissionMonitor::Config MissionMonitor::read_config(ParamReader& p) {
  Config c;
  p.optional("scene", c.scene)
      .doc("the scene, for the coverage over time and the final evaluation (\"\": neither)");
  p.optional("coverage_density_per_m2", c.coverage_density_per_m2, {0.1, 1e5})
      .doc("ground-truth points of the coverage estimate over time (per m²)");
  p.optional("coverage_truncation_share", c.coverage_truncation_share, {0.1, 1})
      .doc("a point is seen when its voxel is observed with |d| < share · μ");
  p.optional("coverage_period_s", c.coverage_period_s, {0.1, 3600})
      .doc("period of the coverage estimate (sim s)");
  p.optional("path_period_s", c.path_period_s, {0.01, 3600})
      .doc("how often each robot's pose goes to paths.csv (s)");
  p.choice("maps", c.maps, kMapSourcesNames)
      .doc(
          "per_robot (single, distributed), shared (the station's) or none (a process that cannot "
          "see the maps)");
  p.optional("stop_when_complete", c.stop_when_complete)
      .doc("stop the mission at the ISE criterion");
  p.optional("stall_timeout_s", c.stall_timeout_s, {0, 1e6})
      .doc("every robot idle (or done) this long stops the mission (s; 0: never)");
  p.optional("eval_density_per_m2", c.eval_density_per_m2, {1, 1e6})
      .doc("ground-truth points for the final evaluation (per m²; thesis: 10,000)");
  p.optional("eval_e_max_m", c.eval_e_max_m, {0, 100})
      .doc("e_max of the final evaluation (m; 0: each mapper's r_v·√3/2, thesis 5.4)");
  p.optional("visibility_rays", c.visibility_rays, {0, 100000})
      .doc("points the scene's meshes hide from every direction are left out (0: off)");
  return c;
}

MissionMonitor::MissionMonitor(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> MissionMonitor::on_configure() {
  if (team().empty() || (team().size() == 1 && team()[0].ns.empty()))
    return make_unexpected(std::string(
        "mission_monitor needs the launch file's robots (each with a namespace) to watch"));
  config_.scene = input_path("scene", config_.scene);
  if (!config_.scene.empty()) {
    auto truth = SurfaceCoverage::from_scene(config_.scene,
                                             {.density_per_m2 = config_.coverage_density_per_m2,
                                              .truncation_share = config_.coverage_truncation_share,
                                              .visibility_rays = config_.visibility_rays},
                                             team_starts());
    if (!truth) return make_unexpected("scene: " + truth.error());
    if (truth->points() == 0)
      return make_unexpected("scene: " + config_.scene +
                             " gives no ground-truth point at coverage_density_per_m2 " +
                             std::to_string(config_.coverage_density_per_m2));
    truth_ = std::move(truth).value();
  }
  const size_t n = team().size();
  robots_.resize(n);
  last_pose_.resize(n);
  have_pose_.assign(n, false);
  idle_since_s_.assign(n, -1.0);
  // maps: none has per-robot ISE sources, like per_robot, without their maps
  const bool per_robot = config_.maps != MapSources::kShared;
  const bool maps = config_.maps != MapSources::kNone;
  sources_.resize(per_robot ? n : 1);
  // without maps (a simulator process) integration is not seen here: not held against
  for (RobotProgress& r : robots_) r.integrated = !maps;
  for (size_t i = 0; i < n; ++i) {
    const TeamMember& m = team()[i];
    robots_[i].id = m.id;
    robots_[i].ns = m.ns;
    robots_[i].kind = m.kind;
    const std::string prefix = "/" + m.ns + "/";
    create_subscription<msg::Odometry>(prefix + "pose_gt", {.depth = 4},
                                       [this, i](Sample<msg::Odometry>&& s) { on_pose(i, *s); });
    if (resolve_in("pose", m.ns) != prefix + "pose_gt") {
      if (!pose_error_) pose_error_.emplace(n);
      create_teammate_subscription<msg::Odometry>(
          "pose", m.ns, {.depth = 4}, [this, i](Sample<msg::Odometry>&& s) { on_estimate(i, *s); });
    }
    create_subscription<msg::RobotState>(
        prefix + "robot_state", {.depth = 8},
        [this, i](Sample<msg::RobotState>&& s) { on_state(i, *s); });
    // a graph without planners (a replay of recorded paths) has no robot states and no ISEs:
    // the monitor then reports coverage only, and the run ends at its duration
    mark_input_optional(prefix + "robot_state");
  }
  for (size_t k = 0; k < sources_.size(); ++k) {
    const std::string prefix = per_robot ? "/" + team()[k].ns + "/" : "/";
    create_subscription<msg::IseSet>(prefix + "ises", {.depth = 1},
                                     [this, k](Sample<msg::IseSet>&& s) { on_ises(k, *s); });
    mark_input_optional(prefix + "ises");
    if (maps)
      create_subscription<msg::MapUpdate>(prefix + "map", {.depth = 1},
                                          [this, k](Sample<msg::MapUpdate>&& s) { on_map(k, *s); });
  }
  create_timer(std::chrono::nanoseconds(std::llround(config_.path_period_s * 1e9)),
               [this] { on_path_tick(); });
  if (truth_ && maps)
    create_timer(std::chrono::nanoseconds(std::llround(config_.coverage_period_s * 1e9)),
                 [this] { on_coverage_tick(); });
  return {};
}

std::vector<eval::TeamStart> MissionMonitor::team_starts() const {
  std::vector<eval::TeamStart> starts;
  for (const TeamMember& m : team()) {
    const bool ground = m.kind == robot::RobotKind::kGround;
    starts.push_back(
        {.kind = m.kind, .position = {m.start_x_m, m.start_y_m, ground ? 0.0 : m.start_z_m}});
  }
  return starts;
}

void MissionMonitor::on_activate() {
  start_ns_ = clock().now_ns();
  accounted_s_ = 0;
}

double MissionMonitor::now_s() {
  return static_cast<double>(clock().now_ns() - start_ns_) * 1e-9;
}

void MissionMonitor::on_pose(size_t robot, const msg::Odometry& odom) {
  const std::lock_guard lock(mutex_);
  if (have_pose_[robot]) {
    const Eigen::Vector3d a = msg::to_eigen(last_pose_[robot].T_world_body.position);
    const Eigen::Vector3d b = msg::to_eigen(odom.T_world_body.position);
    robots_[robot].path_length_m += (b - a).norm();
  }
  last_pose_[robot] = odom;
  have_pose_[robot] = true;
  if (pose_error_) pose_error_->on_truth(robot, odom);
}

void MissionMonitor::on_estimate(size_t robot, const msg::Odometry& odom) {
  const std::lock_guard lock(mutex_);
  pose_error_->on_estimate(robot, odom);
}

void MissionMonitor::summarize(RunSummary& into) const {
  const std::lock_guard lock(mutex_);
  if (!pose_error_) return;
  for (size_t i = 0; i < robots_.size(); ++i) {
    const std::optional<eval::OdometryError> e = pose_error_->robot_error(i);
    if (!e) continue;
    RunSummary::Odometry& o = into.odometry[robots_[i].id];
    o.scored_poses = e->matched;
    o.truth_distance_m = e->distance_m;
    o.ate_rmse_m = e->ate_rmse_m;
    o.ate_max_m = e->ate_max_m;
    o.rpe_mean_percent = e->rpe_mean_percent;
  }
  for (const PoseError::Pair& p : pose_error_->pairs())
    into.frame_misalignment.push_back({.robot_a = robots_[p.a].id,
                                       .robot_b = robots_[p.b].id,
                                       .samples = p.samples,
                                       .mean_m = p.mean_m,
                                       .max_m = p.max_m,
                                       .last_m = p.last_m,
                                       .max_yaw_deg = p.max_yaw_deg});
}

void MissionMonitor::on_state(size_t robot, const msg::RobotState& state) {
  const double t = now_s();
  bool lost_or_back = false;
  {
    const std::lock_guard lock(mutex_);
    RobotProgress& r = robots_[robot];
    if (state.mode == Mode::kPlanning && (!r.have_state || r.mode != Mode::kPlanning))
      ++r.planning_requests;
    const bool was_lost = r.have_state && r.mode == Mode::kLost;
    const bool lost = state.mode == Mode::kLost;
    lost_or_back = lost != was_lost;
    if (lost && !was_lost) {
      last_lost_s_ = t;
      SCANCREW_LOG_WARN(
          "%s: robot %u (%s) lost at %.1f s: left out of the completion and stall tests until "
          "it reports again",
          qualified_name().c_str(), r.id, r.ns.c_str(), t);
    } else if (was_lost && !lost) {
      all_lost_logged_ = false;
      SCANCREW_LOG_INFO("%s: robot %u (%s) back at %.1f s", qualified_name().c_str(), r.id,
                        r.ns.c_str(), t);
    }
    r.mode = state.mode;
    r.have_state = true;
    r.backing_off = state.backing_off;
    r.held_by_robot = state.held_by_robot;
    const bool idle = state.mode == Mode::kIdle || state.mode == Mode::kDone;
    if (!idle)
      idle_since_s_[robot] = -1.0;
    else if (idle_since_s_[robot] < 0)
      idle_since_s_[robot] = t;
  }
  // losing a robot may complete the mission (the others' sources are complete)
  if (lost_or_back) check_finished();
}

void MissionMonitor::on_ises(size_t source, const msg::IseSet& ises) {
  {
    const std::lock_guard lock(mutex_);
    Source& s = sources_[source];
    s.ises_left = ises.inspectable;
    s.have_ises = true;
    s.complete = ises.complete != 0;
    for (size_t i = 0; i < robots_.size(); ++i) {
      if (sources_.size() > 1 && i != source) continue;
      robots_[i].ises_left = s.ises_left;
      robots_[i].have_ises = true;
      robots_[i].complete = s.complete;
    }
  }
  check_finished();
}

void MissionMonitor::on_map(size_t source, const msg::MapUpdate& update) {
  const std::lock_guard lock(mutex_);
  sources_[source].map = update.map;
  for (RobotProgress& r : robots_)
    if (std::binary_search(update.robots_integrated.begin(), update.robots_integrated.end(), r.id))
      r.integrated = true;
}

void MissionMonitor::account_time(double t) {
  const double dt = t - accounted_s_;
  if (dt <= 0) return;
  accounted_s_ = t;
  const bool per_robot = config_.maps != MapSources::kShared;
  for (size_t i = 0; i < robots_.size(); ++i) {
    RobotProgress& r = robots_[i];
    report::ActivityInputs in{.have_state = r.have_state,
                              .mode = r.mode,
                              .backing_off = r.backing_off,
                              .held_by_robot = r.held_by_robot,
                              .source_complete = sources_[per_robot ? i : 0].complete};
    if (have_pose_[i]) {
      in.speed_mps = msg::to_eigen(last_pose_[i].linear_velocity_mps).norm();
      in.yaw_rate_radps = last_pose_[i].angular_velocity_radps.z;
    }
    r.time.add(report::classify(in), dt);
  }
}

void MissionMonitor::close_time_breakdown() {
  const std::lock_guard lock(mutex_);
  account_time(now_s());
}

std::vector<std::string> MissionMonitor::robots_without_depth() const {
  const std::lock_guard lock(mutex_);
  std::vector<std::string> missing;
  if (!depth_required_) return missing;
  for (const RobotProgress& r : robots_)
    if (!r.integrated && !(r.have_state && r.mode == Mode::kLost)) missing.push_back(r.ns);
  return missing;
}

void MissionMonitor::on_path_tick() {
  const double t = now_s();
  {
    const std::lock_guard lock(mutex_);
    account_time(t);
    if (pose_error_) pose_error_->sample(clock().now_ns());
    for (size_t i = 0; i < robots_.size(); ++i) {
      if (!have_pose_[i]) continue;
      const msg::Pose3& p = last_pose_[i].T_world_body;
      paths_.push_back({.t_s = t,
                        .robot_id = robots_[i].id,
                        .x_m = p.position.x,
                        .y_m = p.position.y,
                        .z_m = p.position.z,
                        .yaw_rad = yaw_of(p)});
    }
  }
  check_finished();
}

void MissionMonitor::on_coverage_tick() {
  const double t = now_s();
  std::vector<std::shared_ptr<const tsdf::MapSnapshot>> maps;
  std::vector<bool> fresh;
  {
    const std::lock_guard lock(mutex_);
    for (Source& s : sources_) {
      maps.push_back(s.map);
      fresh.push_back(s.map && s.map->sequence() != s.map_version_measured);
    }
  }
  // measured outside the lock: the snapshots are immutable
  std::vector<CoverageShare> measured(maps.size(), {.all = -1.0});
  for (size_t k = 0; k < maps.size(); ++k)
    if (fresh[k]) measured[k] = truth_->measure_shares(*maps[k]);
  const std::lock_guard lock(mutex_);
  for (size_t k = 0; k < maps.size(); ++k) {
    if (measured[k].all >= 0) sources_[k].map_version_measured = maps[k]->sequence();
    for (size_t i = 0; i < robots_.size(); ++i) {
      if (sources_.size() > 1 && i != k) continue;
      if (measured[k].all >= 0) {
        robots_[i].coverage = measured[k].all;
        robots_[i].coverage_reachable = measured[k].reachable;
      }
      if (robots_[i].coverage < 0) continue;
      coverage_.push_back({.t_s = t,
                           .robot_id = robots_[i].id,
                           .coverage = robots_[i].coverage,
                           .coverage_reachable = robots_[i].coverage_reachable,
                           .ises_left = robots_[i].ises_left});
    }
  }
}

void MissionMonitor::check_finished() {
  const double t = now_s();
  const std::lock_guard lock(mutex_);
  if (!stop_reason_.empty()) return;
  const auto lost = [this](size_t i) {
    return robots_[i].have_state && robots_[i].mode == Mode::kLost;
  };
  size_t lost_count = 0;
  for (size_t i = 0; i < robots_.size(); ++i) lost_count += lost(i) ? 1 : 0;
  const bool all_lost = lost_count == robots_.size();
  if (all_lost && !all_lost_logged_) {
    all_lost_logged_ = true;
    SCANCREW_LOG_WARN("%s: every robot lost at %.1f s: the mission is not complete%s",
                      qualified_name().c_str(), t,
                      config_.stall_timeout_s > 0 ? "; it stalls unless one comes back" : "");
  }
  // per-robot sources (per_robot, none): a lost robot's source is left out; the shared one
  // decides alone
  const bool per_robot = config_.maps != MapSources::kShared;
  bool all_complete = !(per_robot && all_lost);
  for (size_t k = 0; k < sources_.size(); ++k)
    if (!(per_robot && lost(k))) all_complete = all_complete && sources_[k].complete;
  // a robot whose depth never reached a map has seen nothing: its source's empty C_ins
  // says nothing about the scene (an unconnected depth topic, a camera that never fired)
  std::string without_depth;
  for (size_t i = 0; i < robots_.size() && depth_required_; ++i)
    if (!lost(i) && !robots_[i].integrated)
      without_depth += (without_depth.empty() ? "" : ", ") + robots_[i].ns;
  if (all_complete && !without_depth.empty()) {
    if (!no_depth_logged_)
      SCANCREW_LOG_WARN(
          "%s: the ISE sources report completion at %.1f s, but no map has "
          "integrated a depth image of %s yet: not complete",
          qualified_name().c_str(), t, without_depth.c_str());
    no_depth_logged_ = true;
    all_complete = false;
  }
  if (all_complete && config_.stop_when_complete) {
    completion_time_s_ = t;
    stop_reason_ = "complete";
    SCANCREW_LOG_INFO("%s: mission complete at %.1f s (every ISE source reports C_ins empty%s)",
                      qualified_name().c_str(), t,
                      per_robot && lost_count > 0 ? ", lost robots left out" : "");
    return;
  }
  if (config_.stall_timeout_s <= 0) return;
  bool all_idle = true;
  for (size_t i = 0; i < robots_.size(); ++i)
    all_idle =
        all_idle &&
        (lost(i) || (idle_since_s_[i] >= 0 && t - idle_since_s_[i] >= config_.stall_timeout_s));
  if (all_lost) all_idle = t - last_lost_s_ >= config_.stall_timeout_s;
  if (all_idle) {
    stop_reason_ = "stalled";
    SCANCREW_LOG_WARN("%s: mission stalled at %.1f s: every robot %s for %.0f s with ISEs left",
                      qualified_name().c_str(), t,
                      all_lost ? "lost" : (lost_count > 0 ? "idle or lost" : "idle"),
                      config_.stall_timeout_s);
  }
}

std::vector<MissionMonitor::RobotProgress> MissionMonitor::robots() const {
  const std::lock_guard lock(mutex_);
  return robots_;
}

std::vector<report::PathSample> MissionMonitor::paths() const {
  const std::lock_guard lock(mutex_);
  return paths_;
}

std::vector<report::CoverageSample> MissionMonitor::coverage() const {
  const std::lock_guard lock(mutex_);
  return coverage_;
}

bool MissionMonitor::finished() const {
  const std::lock_guard lock(mutex_);
  return !stop_reason_.empty();
}

std::string MissionMonitor::stop_reason() const {
  const std::lock_guard lock(mutex_);
  return stop_reason_;
}

std::optional<double> MissionMonitor::completion_time_s() const {
  const std::lock_guard lock(mutex_);
  return completion_time_s_;
}

std::string MissionMonitor::status_line() const {
  const std::lock_guard lock(mutex_);
  std::string line;
  char buf[160];
  for (const RobotProgress& r : robots_) {
    std::string cov = r.coverage >= 0 ? std::to_string(std::lround(100 * r.coverage)) + " %" : "-";
    std::snprintf(buf, sizeof buf, "%s%s %s %s %s ISE", line.empty() ? "" : " | ", r.ns.c_str(),
                  r.have_state ? msg::to_string(r.mode) : "starting", cov.c_str(),
                  r.have_ises ? std::to_string(r.ises_left).c_str() : "-");
    line += buf;
  }
  return line;
}

SCANCREW_REGISTER_COMPONENT(MissionMonitor, "mission_monitor")

}  // namespace scancrew::mission_monitor
