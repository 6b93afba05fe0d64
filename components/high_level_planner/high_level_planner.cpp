#include "components/high_level_planner/high_level_planner.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "components/low_level_planner/planner_params.hpp"
#include "core/motion/motion_planner.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"
#include "interfaces/map_update.hpp"

namespace scancrew::high_level_planner {

using tsga::RobotPlan;
using tsga::ViewpointRef;

namespace {

constexpr uint32_t kGroundBit = msg::kGroundRobotBit;
constexpr uint32_t kMultirotorBit = msg::kMultirotorBit;

void read_penalties(ParamReader& p, const std::string& type, HighLevelPlanner::Penalties& out) {
  p.optional(type + "_lambda_tc_per_m", out.lambda_tc_per_m, {0, 100})
      .doc("λ_tc of this robot kind (per m; tables 5.3, 2.2)");
  p.optional(type + "_lambda_ic_per_m", out.lambda_ic_per_m, {0, 100})
      .doc("λ_ic of this robot kind (per m; tables 5.3, 2.2)");
}

Eigen::Vector3d vec(const msg::Vec3& v) {
  return {v.x, v.y, v.z};
}

msg::Vec3 vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// One plan's roadmap distances: every viewpoint is a target (the planner enters a cluster
// at one of them), each (robot type, starting point) gets one roadmap_distances() row from
// that type's roadmap. Points are matched exactly: the planner passes on the positions it
// was given.
struct RoadmapMemo {
  using Key = std::array<double, 3>;
  static Key key(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }
  std::vector<msg::Waypoint> targets;
  std::map<Key, size_t> target_index;
  std::map<Key, double> yaw;  // of the viewpoints and the robots
  // per (robot type bit, starting point); empty: the straight line from there
  std::map<std::pair<uint32_t, Key>, std::vector<double>> rows;
};

}  // namespace

HighLevelPlanner::Config HighLevelPlanner::read_config(ParamReader& p) {
  Config c;
  p.choice("algorithm", c.algorithm, kAlgorithmNames)
      .doc(
          "tsga (centralized: all sequences), dist_tsga (per robot: its own sequence) or nnb "
          "(either)");
  p.choice("inter_cluster_distance", c.inter_cluster_distance, kInterClusterDistanceNames)
      .doc(
          "d(τ_kl): euclidean (straight line) or roadmap (the low-level planner's path length over "
          "its LazyPRM* roadmap)");
  read_penalties(p, "ground", c.ground);
  read_penalties(p, "multirotor", c.multirotor);
  p.optional("insertion_iterations", c.options.insertion_iterations, {0, 100000})
      .doc("the TSP engine's budget: iterations per insertion");
  p.optional("final_iterations", c.options.final_iterations, {0, 1000000})
      .doc("the TSP engine's budget: iterations of the final search");
  p.optional("seed", c.options.seed).doc("the TSP engine's random seed");
  p.choice("allocation_gain", c.options.gain, tsga::kGainNames)
      .doc("the gain the allocation weighs: arc or arrival (docs/tsga.md)");
  p.optional("min_replan_period_s", c.min_replan_period_s, {0, 1e6})
      .doc("sim seconds between two plans on cluster updates (0: every update)");
  p.optional("keep_intra_paths", c.keep_intra_paths)
      .doc(
          "a cluster whose viewpoints are those of the last plan keeps its intra-cluster path "
          "(same plans, faster)");
  p.optional("idle_teammate_s", c.idle_teammate_s, {0, 1e6})
      .doc("dist_tsga: plan without a teammate idle this long (s; 0: never)");
  c.roadmap = low_level_planner::read_planner_config(p);
  return c;
}

HighLevelPlanner::HighLevelPlanner(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

HighLevelPlanner::~HighLevelPlanner() = default;

Result<void, std::string> HighLevelPlanner::on_configure() {
  per_robot_ = robot_id() != 0;
  if (config_.algorithm == Algorithm::kDistTsga && !per_robot_)
    return make_unexpected("algorithm dist_tsga runs on every robot: set per_robot: true");
  if (config_.algorithm == Algorithm::kTsga && per_robot_)
    return make_unexpected(
        "algorithm tsga is the centralized planner: set per_robot: false (dist_tsga is the "
        "per-robot one)");
  if (team().empty()) return make_unexpected("the launch file has no robots to plan for");
  if (config_.inter_cluster_distance == InterClusterDistance::kRoadmap)
    if (auto roadmaps = configure_roadmaps(); !roadmaps) return roadmaps;
  for (size_t i = 0; i < team().size(); ++i) {
    const TeamMember& t = team()[i];
    Member m;
    m.id = t.id;
    const bool multirotor = t.kind == robot::RobotKind::kMultirotor;
    m.type_bit = multirotor ? kMultirotorBit : kGroundBit;
    m.penalties = multirotor ? config_.multirotor : config_.ground;
    m.position = {t.start_x_m, t.start_y_m, t.start_z_m};
    m.yaw_rad = t.start_yaw_rad;
    members_.push_back(m);
    const std::string ns = "/" + t.ns + "/";
    create_teammate_subscription<msg::Odometry>(
        "pose", t.ns, {.depth = 1}, [this, i](Sample<msg::Odometry>&& s) {
          const msg::Vec3& p = s->T_world_body.position;
          if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
            members_[i].position = vec(p);
            const double yaw = yaw_of(s->T_world_body.orientation);
            if (std::isfinite(yaw)) members_[i].yaw_rad = yaw;
          } else
            fail_once("pose", "a non-finite pose of robot " + std::to_string(members_[i].id) +
                                  " (ignored; its last position stands)");
        });
    create_subscription<msg::RobotState>(
        ns + "robot_state", {.depth = 4},
        [this, i](Sample<msg::RobotState>&& s) { on_robot_state(i, *s); });
    // after the state: the step executor delivers in subscription order, and a request
    // is planned on the pose of the state sent with it
    create_subscription<msg::ReplanRequest>(
        ns + "replan_request", {.depth = 4},
        [this, i](Sample<msg::ReplanRequest>&& s) { on_replan_request(i, *s); });
    mark_input_optional(ns + "replan_request");  // a graph without low-level planners
  }
  last_.robots.resize(members_.size());
  for (size_t i = 0; i < members_.size(); ++i) last_.robots[i].robot_id = members_[i].id;
  plan_pub_ = create_publisher<msg::TeamPlan>("plan", {.pool_size = 2});
  create_subscription<msg::ViewpointClusters>(
      "clusters", {.depth = 1}, [this](Sample<msg::ViewpointClusters>&& s) { on_clusters(*s); });
  create_subscription<msg::IseSet>("ises", {.depth = 1},
                                   [this](Sample<msg::IseSet>&& s) { ises_ = *s; });
  return {};
}

// One roadmap MotionPlanner per robot kind in the team (keyed by its type bit), all
// following the `map` topic.
Result<void, std::string> HighLevelPlanner::configure_roadmaps() {
  for (const TeamMember& t : team()) {
    const bool multirotor = t.kind == robot::RobotKind::kMultirotor;
    const uint32_t bit = multirotor ? kMultirotorBit : kGroundBit;
    if (roadmaps_.contains(bit)) continue;
    motion::PlannerConfig pc = config_.roadmap;
    pc.robot_kind = t.kind;
    auto planner = motion::MotionPlanner::create(pc);
    if (!planner) return make_unexpected(planner.error());
    roadmaps_.emplace(bit, std::make_unique<motion::MotionPlanner>(std::move(planner).value()));
  }
  create_subscription<msg::MapUpdate>("map", {.depth = 1}, [this](Sample<msg::MapUpdate>&& s) {
    if (s->map == nullptr) return;
    for (auto& [bit, roadmap] : roadmaps_) roadmap->update_map(s->map, s->header.stamp_ns);
    have_map_ = true;
  });
  return {};
}

void HighLevelPlanner::on_clusters(const msg::ViewpointClusters& clusters) {
  clusters_ = clusters;
  plan_clusters_.clear();
  plan_clusters_.reserve(clusters.clusters.size());
  for (const msg::ViewpointCluster& c : clusters.clusters) {
    PlanCluster pc{.id = c.id, .gain = c.gain, .robot_types = c.robot_types, .viewpoints = {}};
    pc.viewpoints.reserve(c.viewpoints.size());
    for (const msg::Viewpoint& v : c.viewpoints) pc.viewpoints.push_back(vec(v.pose.position));
    plan_clusters_.push_back(std::move(pc));
  }
  const int64_t stamp = clusters.header.stamp_ns;
  const auto period_ns = static_cast<int64_t>(config_.min_replan_period_s * 1e9);
  if (last_plan_stamp_ns_ && stamp - *last_plan_stamp_ns_ < period_ns) {
    ++stats_.skipped;
    return;
  }
  plan(stamp, std::nullopt);
}

bool HighLevelPlanner::idle_too_long(size_t member) const {
  const Member& m = members_[member];
  return config_.idle_teammate_s > 0 && per_robot_ && m.id != robot_id() && m.idle_since_ns >= 0 &&
         static_cast<double>(plan_stamp_ns_ - m.idle_since_ns) * 1e-9 >= config_.idle_teammate_s;
}

bool HighLevelPlanner::lost(size_t member) const {
  // a per-robot instance's own robot runs it: never lost to it
  return members_[member].mode == msg::RobotState::Mode::kLost &&
         !(per_robot_ && members_[member].id == robot_id());
}

void HighLevelPlanner::on_robot_state(size_t member, const msg::RobotState& state) {
  using Mode = msg::RobotState::Mode;
  const bool was_lost = lost(member);
  const Mode before = members_[member].mode;
  members_[member].mode = state.mode;
  const bool idle_now = state.mode == Mode::kIdle || state.mode == Mode::kDone;
  if (!idle_now)
    members_[member].idle_since_ns = -1;
  else if (members_[member].idle_since_ns < 0)
    members_[member].idle_since_ns = state.header.stamp_ns;
  // a kLost state is the bridge's word for a dead process: its pose means nothing
  const msg::Vec3& p = state.T_world_body.position;
  if (state.mode != Mode::kLost && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
    members_[member].position = vec(p);
    const double yaw = yaw_of(state.T_world_body.orientation);
    if (std::isfinite(yaw)) members_[member].yaw_rad = yaw;
  }
  if (lost(member) != was_lost) {
    SCANCREW_LOG_INFO("%s: robot %u %s", qualified_name().c_str(), members_[member].id,
                      was_lost ? "is back: planned for again"
                               : "lost: left out of the plans, its clusters go to the others");
    // every instance plans for the whole team (dist_tsga: each keeps its own sequence of
    // the same allocation), so each re-plans, whoever's robot it is
    if (!clusters_) return;
    ++stats_.lost_replans;
    plan(state.header.stamp_ns, std::nullopt);
    return;
  }
  if (!clusters_ || state.mode == before) return;
  // only the robots this instance plans for: all (centralized) or its own (per robot)
  if (per_robot_ && members_[member].id != robot_id()) return;
  if (state.mode == Mode::kIdle) {
    const bool realloc = config_.algorithm == Algorithm::kTsga;
    plan(state.header.stamp_ns, realloc ? std::optional<size_t>(member) : std::nullopt);
  }
}

void HighLevelPlanner::on_replan_request(size_t member, const msg::ReplanRequest& request) {
  if (!clusters_ || lost(member)) return;
  // only the robots this instance plans for: all (centralized) or its own (per robot)
  if (per_robot_ && members_[member].id != robot_id()) return;
  ++stats_.requests;
  SCANCREW_LOG_DEBUG("%s: robot %u asks for a new plan (%s%s)", qualified_name().c_str(),
                     members_[member].id, to_string(request.reason),
                     request.repeated ? ", again" : "");
  plan(request.header.stamp_ns, std::nullopt);
}

std::vector<size_t> HighLevelPlanner::plan_members() const {
  std::vector<size_t> active;
  active.reserve(members_.size());
  for (size_t i = 0; i < members_.size(); ++i)
    if (!lost(i) && !idle_too_long(i)) active.push_back(i);
  return active;
}

std::vector<PlanRobot> HighLevelPlanner::plan_robots() const {
  const std::vector<size_t> active = plan_members();
  std::vector<PlanRobot> robots;
  robots.reserve(active.size());
  for (size_t i : active) {
    const Member& m = members_[i];
    robots.push_back({.id = m.id,
                      .type_bit = m.type_bit,
                      .position = m.position,
                      .lambda_tc_per_m = m.penalties.lambda_tc_per_m,
                      .lambda_ic_per_m = m.penalties.lambda_ic_per_m});
  }
  return robots;
}

PlannerOptions HighLevelPlanner::plan_options() {
  PlannerOptions options = config_.options;
  if (config_.keep_intra_paths) {
    intra_paths_.new_generation();
    options.intra_paths = &intra_paths_;
  }
  if (roadmaps_.empty()) return options;
  if (!have_map_) {
    warn_once("roadmap_no_map",
              "inter_cluster_distance: roadmap: no map on `map` yet; d(τ_kl) is the straight "
              "line until the first one");
    return options;
  }
  auto memo = std::make_shared<RoadmapMemo>();
  for (const msg::ViewpointCluster& c : clusters_->clusters)
    for (const msg::Viewpoint& v : c.viewpoints) {
      const RoadmapMemo::Key k = RoadmapMemo::key(vec(v.pose.position));
      memo->yaw.emplace(k, v.pose.yaw_rad);
      if (memo->target_index.emplace(k, memo->targets.size()).second)
        memo->targets.push_back(v.pose);
    }
  for (const Member& m : members_) memo->yaw[RoadmapMemo::key(m.position)] = m.yaw_rad;
  options.travel_distance = [this, memo](uint32_t type_bit, const Eigen::Vector3d& from,
                                         const Eigen::Vector3d& to) {
    const auto roadmap = roadmaps_.find(type_bit);
    if (roadmap == roadmaps_.end()) return std::numeric_limits<double>::infinity();
    const auto row_key = std::make_pair(type_bit, RoadmapMemo::key(from));
    auto row = memo->rows.find(row_key);
    if (row == memo->rows.end()) {
      msg::Waypoint w;
      w.position = vec(from);
      const auto yaw = memo->yaw.find(RoadmapMemo::key(from));
      w.yaw_rad = yaw != memo->yaw.end() ? yaw->second : 0.0;
      motion::RoadmapDistances d = roadmap->second->roadmap_distances(w, memo->targets);
      ++stats_.roadmap_queries;
      stats_.roadmap_ms += d.ms;
      if (d.status != motion::PlanStatus::kOk) {
        ++stats_.straight_fallbacks;
        char where[96];
        std::snprintf(where, sizeof where, "(%.2f, %.2f, %.2f)", from.x(), from.y(), from.z());
        warn_once("roadmap_" + std::string(motion::to_string(d.status)),
                  "inter_cluster_distance: roadmap: no roadmap distances from " +
                      std::string(where) + ": " + d.message +
                      "; the straight line is used from such points");
        d.distances_m.clear();
      }
      row = memo->rows.emplace(row_key, std::move(d.distances_m)).first;
    }
    const auto target = memo->target_index.find(RoadmapMemo::key(to));
    if (row->second.empty() || target == memo->target_index.end()) return (to - from).norm();
    return row->second[target->second];
  };
  return options;
}

void HighLevelPlanner::plan(int64_t stamp_ns, std::optional<size_t> idle) {
  if (!clusters_) return;
  plan_stamp_ns_ = stamp_ns;
  const auto start = std::chrono::steady_clock::now();
  // the members planned for (lost ones left out) and their PlanRobots, in the same order
  const std::vector<size_t> active = plan_members();
  if (active.empty()) {
    warn_once("all_lost", "every robot of the team is lost: nothing to plan until one is back");
    return;
  }
  const std::vector<PlanRobot> robots = plan_robots();
  const PlannerOptions options = plan_options();
  TeamPlan next = last_;
  if (idle) {
    const auto at = std::find(active.begin(), active.end(), *idle);
    if (at == active.end()) return;  // (a lost robot is not idle)
    // the clusters the others hold: a lost robot holds none
    std::vector<uint32_t> held;
    for (size_t k : active)
      if (k != *idle)
        held.insert(held.end(), last_.robots[k].clusters.begin(), last_.robots[k].clusters.end());
    auto mine = plan_for_idle(robots[static_cast<size_t>(at - active.begin())], plan_clusters_,
                              held, options);
    if (!mine) return fail_once("clusters", mine.error());
    next.robots[*idle] = std::move(mine).value();
    ++stats_.reallocations;
  } else {
    auto team = config_.algorithm == Algorithm::kNnb ? plan_nnb(robots, plan_clusters_, options)
                                                     : plan_tsga(robots, plan_clusters_, options);
    if (!team) return fail_once("clusters", team.error());
    // back to one RobotPlan per member: a lost member's is empty
    next.unassigned = std::move(team->unassigned);
    for (size_t k = 0; k < members_.size(); ++k) next.robots[k] = {.robot_id = members_[k].id};
    for (size_t j = 0; j < active.size(); ++j) next.robots[active[j]] = std::move(team->robots[j]);
  }
  last_ = std::move(next);
  last_plan_stamp_ns_ = stamp_ns;
  const double ms = ms_since(start);
  ++stats_.plans;
  ms_sum_ += ms;
  stats_.intra_paths = intra_paths_.stats();
  stats_.max_ms = std::max(stats_.max_ms, ms);
  stats_.mean_ms = ms_sum_ / static_cast<double>(stats_.plans);
  // after a reallocation to an idle robot only its sequence is new: the others' were
  // planned on older clusters, whose viewpoints their references index (a cluster of that
  // id may now hold fewer: an out-of-range crash in an outdoor trio), and a plan without a
  // robot's sequence leaves its tour as it is
  publish(last_, stamp_ns, idle);
}

void HighLevelPlanner::publish(const TeamPlan& plan, int64_t stamp_ns, std::optional<size_t> only) {
  auto loan = plan_pub_.loan();
  if (!loan) return;
  msg::TeamPlan& m = **loan;
  m.header.stamp_ns = stamp_ns;
  m.plan_id = ++plan_id_;
  m.map_version = clusters_->map_version;
  m.sequences.clear();
  m.unassigned = plan.unassigned;
  // cluster id -> its message, to fetch yaws and seen ISEs
  std::map<uint32_t, const msg::ViewpointCluster*> by_id;
  for (const msg::ViewpointCluster& c : clusters_->clusters) by_id[c.id] = &c;
  const bool ises_match = ises_ && ises_->map_version == clusters_->map_version;
  for (size_t k = 0; k < plan.robots.size(); ++k) {
    const RobotPlan& r = plan.robots[k];
    if (per_robot_ && r.robot_id != robot_id()) continue;
    if (only && k != *only) continue;
    msg::PathSequence s;
    s.robot_id = r.robot_id;
    s.cluster_ids = r.clusters;
    s.cluster_utilities = r.utilities;
    s.utility = r.utility;
    std::vector<uint32_t> seen;
    for (const ViewpointRef& ref : r.viewpoint_refs) {
      const msg::Viewpoint& v = by_id.at(ref.cluster_id)->viewpoints.at(ref.index);
      s.viewpoints.push_back(v.pose);
      s.viewpoint_clusters.push_back(ref.cluster_id);
      seen.insert(seen.end(), v.seen_ise.begin(), v.seen_ise.end());
    }
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    if (ises_match)
      for (uint32_t i : seen)
        if (i < ises_->centers_m.size()) s.ise_centers_m.push_back(ises_->centers_m[i]);
    m.sequences.push_back(std::move(s));
  }
  (void)plan_pub_.publish(std::move(*loan));
}

void HighLevelPlanner::fail_once(const std::string& kind, const std::string& message) {
  ++stats_.skipped;
  if (failures_logged_[kind]) return;
  failures_logged_[kind] = true;
  SCANCREW_LOG_ERROR("%s: %s (the last plan stands; further such errors are counted, not logged)",
                     qualified_name().c_str(), message.c_str());
}

void HighLevelPlanner::warn_once(const std::string& kind, const std::string& message) {
  if (failures_logged_[kind]) return;
  failures_logged_[kind] = true;
  SCANCREW_LOG_WARN("%s: %s (logged once)", qualified_name().c_str(), message.c_str());
}

void HighLevelPlanner::on_deactivate() {
  SCANCREW_LOG_INFO(
      "%s: %s: %llu plans (%.1f ms mean, %.1f max), %llu reallocations to idle robots, %llu "
      "updates skipped",
      qualified_name().c_str(), std::string(name_of(kAlgorithmNames, config_.algorithm)).c_str(),
      static_cast<unsigned long long>(stats_.plans), stats_.mean_ms, stats_.max_ms,
      static_cast<unsigned long long>(stats_.reallocations),
      static_cast<unsigned long long>(stats_.skipped));
  if (config_.keep_intra_paths)
    SCANCREW_LOG_INFO(
        "%s: intra-cluster paths: %llu kept, %llu found (%.1f ms in all)", qualified_name().c_str(),
        static_cast<unsigned long long>(stats_.intra_paths.hits),
        static_cast<unsigned long long>(stats_.intra_paths.misses), stats_.intra_paths.solve_ms);
  if (!roadmaps_.empty())
    SCANCREW_LOG_INFO(
        "%s: roadmap distances: %llu queries (%.1f ms mean), %llu starting points measured by "
        "the straight line",
        qualified_name().c_str(), static_cast<unsigned long long>(stats_.roadmap_queries),
        stats_.roadmap_queries > 0 ? stats_.roadmap_ms / static_cast<double>(stats_.roadmap_queries)
                                   : 0.0,
        static_cast<unsigned long long>(stats_.straight_fallbacks));
}

SCANCREW_REGISTER_COMPONENT(HighLevelPlanner, "high_level_planner")

}  // namespace scancrew::high_level_planner
