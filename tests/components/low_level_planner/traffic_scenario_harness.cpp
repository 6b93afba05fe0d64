// The traffic scenarios' harness (traffic_scenario_harness.hpp): the tour feeder, the test
// components' registrations, the truth's geometry, running a scenario and the shared checks.

#include "tests/components/low_level_planner/traffic_scenario_harness.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "executors/registry.hpp"

namespace scancrew::low_level_planner::scenario_harness {
namespace {

// Stands in for the high-level planner: sends each robot its fixed tour (plan 1 at the
// first tick) and answers every replanning request (an entry into kPlanning) with the
// goals the robot has not reached yet, under a new plan id.
//   tours: [robot_id, x, y, z, yaw_deg] quintuples, in visiting order per robot
class TourFeeder final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "test: fixed tours for the low-level planners; answers replanning requests";
  struct Config {
    std::vector<double> tours;
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional_list("tours", c.tours);
    if (c.tours.size() % 5 != 0) p.report("tours", "must hold [id, x, y, z, yaw_deg] quintuples");
    return c;
  }
  TourFeeder(ComponentContext c, Config config)
      : Component(std::move(c)), config_(std::move(config)) {}

  uint64_t plans_sent() const { return plans_sent_; }

 private:
  struct Robot {
    uint32_t id = 0;
    std::vector<msg::Waypoint> goals;
    Publisher<msg::TeamPlan> plan;
    size_t offset = 0;  // the goal the current plan starts at
    uint64_t plan_id = 0;
    Mode last_mode = Mode::kIdle;
    bool due = true;
  };

  Result<void, std::string> on_configure() override {
    robots_.reserve(team().size());
    for (const TeamMember& m : team()) {
      Robot r;
      r.id = m.id;
      for (size_t k = 0; k + 4 < config_.tours.size(); k += 5)
        if (static_cast<uint32_t>(config_.tours[k]) == m.id)
          r.goals.push_back(
              {.position = {config_.tours[k + 1], config_.tours[k + 2], config_.tours[k + 3]},
               .yaw_rad = config_.tours[k + 4] * M_PI / 180});
      r.plan = create_publisher<msg::TeamPlan>("/" + m.ns + "/plan");
      robots_.push_back(std::move(r));
    }
    for (size_t i = 0; i < robots_.size(); ++i)
      create_subscription<msg::RobotState>(
          "/" + team()[i].ns + "/robot_state", {.depth = 4},
          [this, i](Sample<msg::RobotState>&& s) {
            Robot& r = robots_[i];
            if (s->mode == Mode::kPlanning && r.last_mode != Mode::kPlanning &&
                s->plan_id == r.plan_id) {
              r.offset = std::min(r.goals.size(), r.offset + s->path_index);
              r.due = true;
            }
            r.last_mode = s->mode;
          });
    create_timer(std::chrono::milliseconds(100), [this] { tick(); });
    return {};
  }

  void tick() {
    for (Robot& r : robots_) {
      if (!r.due) continue;
      auto loan = r.plan.loan();
      if (!loan) continue;
      r.due = false;
      r.plan_id = ++next_plan_id_;
      msg::TeamPlan& plan = **loan;
      plan = msg::TeamPlan{};
      plan.header.stamp_ns = clock().now_ns();
      plan.plan_id = r.plan_id;
      msg::PathSequence s;
      s.robot_id = r.id;
      for (size_t k = r.offset; k < r.goals.size(); ++k) {
        s.cluster_ids.push_back(static_cast<uint32_t>(k + 1));
        s.viewpoints.push_back(r.goals[k]);
        s.viewpoint_clusters.push_back(static_cast<uint32_t>(k + 1));
      }
      plan.sequences.push_back(std::move(s));
      (void)r.plan.publish(std::move(*loan));
      ++plans_sent_;
    }
  }

  Config config_;
  std::vector<Robot> robots_;
  uint64_t next_plan_id_ = 0;
  uint64_t plans_sent_ = 0;
};

double point_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

}  // namespace

SCANCREW_REGISTER_COMPONENT(TourFeeder, "test_tour_feeder")
SCANCREW_REGISTER_COMPONENT(RobotLog, "test_robot_log")
SCANCREW_REGISTER_COMPONENT(PoseProbe, "test_pose_probe")

// --- geometry of the truth -------------------------------------------------------------

bool overlap(const Rect& a, const Rect& b) {
  const auto ca = a.corners(), cb = b.corners();
  for (const Rect* r : {&a, &b})
    for (double angle : {r->yaw_rad, r->yaw_rad + M_PI / 2}) {
      const Eigen::Vector2d axis(std::cos(angle), std::sin(angle));
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (const auto& c : ca) {
        amin = std::min(amin, c.dot(axis));
        amax = std::max(amax, c.dot(axis));
      }
      for (const auto& c : cb) {
        bmin = std::min(bmin, c.dot(axis));
        bmax = std::max(bmax, c.dot(axis));
      }
      if (amax < bmin || bmax < amin) return false;
    }
  return true;
}

double gap(const Rect& a, const Rect& b) {
  if (overlap(a, b)) return 0;
  const auto ca = a.corners(), cb = b.corners();
  double d = 1e300;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      d = std::min(d, point_segment(ca[i], cb[j], cb[(j + 1) % 4]));
      d = std::min(d, point_segment(cb[i], ca[j], ca[(j + 1) % 4]));
    }
  return d;
}

Truth load_truth(const std::string& path) {
  Truth t;
  auto scene = sim::load_scene(path);
  EXPECT_TRUE(scene) << (scene ? "" : scene.error().front());
  if (!scene) return t;
  t.scene = *scene;
  const sim::SceneSpec& s = t.scene;
  const auto add = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& size, double yaw) {
    t.solids.push_back({.center = c.head<2>(), .half = 0.5 * size.head<2>(), .yaw_rad = yaw});
    t.geometry.add_box(c, size, yaw);
  };
  if (s.wall_height_m > 0) {  // as sim/mjcf_builder.cpp builds them: inner faces on the bounds
    const double w = s.wall_thickness_m, h = s.wall_height_m;
    const double sx = s.max_m.x - s.min_m.x, sy = s.max_m.y - s.min_m.y;
    const double cx = 0.5 * (s.min_m.x + s.max_m.x), cy = 0.5 * (s.min_m.y + s.max_m.y);
    add({cx, s.max_m.y + 0.5 * w, 0.5 * h}, {sx + 2 * w, w, h}, 0);
    add({cx, s.min_m.y - 0.5 * w, 0.5 * h}, {sx + 2 * w, w, h}, 0);
    add({s.max_m.x + 0.5 * w, cy, 0.5 * h}, {w, sy, h}, 0);
    add({s.min_m.x - 0.5 * w, cy, 0.5 * h}, {w, sy, h}, 0);
  }
  for (const sim::BoxSpec& b : s.boxes)
    add({b.center_m.x, b.center_m.y, b.center_m.z}, {b.size_m.x, b.size_m.y, b.size_m.z},
        b.yaw_rad);
  return t;
}

double scene_gap(const Truth& truth, const Eigen::Vector3d& pose) {
  double d = 1e300;
  for (const Rect& r : truth.solids) d = std::min(d, gap(footprint(pose), r));
  return d;
}

// --- running a scenario ----------------------------------------------------------------

std::string scene_path(const std::string& name) {
  const std::string root = SCANCREW_SOURCE_DIR;
  return root + "/tests/components/low_level_planner/scenes/" + name;
}

std::string low_level_with_defaults(const std::string& params) {
  std::string all = params;
  for (const char* d :
       {"unknown_is_occupied: false", "planner_time_limit_s: 1.0", "planner_seed: 1"}) {
    const std::string key = std::string(d).substr(0, std::string(d).find(':') + 1);
    if (params.find(key) == std::string::npos)
      all = std::string(d) + (all.empty() ? "" : ", ") + all;
  }
  return all;
}

std::string launch_text(const std::string& scene, const std::vector<RobotSetup>& robots,
                        double duration_s, const std::string& low_level_params) {
  std::string text =
      "clock: sim\nexecutor: {type: step}\nrun: {duration_s: " + std::to_string(duration_s) +
      ", sim_step_s: 0.05}\nrobots:\n";
  std::string tours;
  for (const RobotSetup& r : robots) {
    text += "  - {id: " + std::to_string(r.id) + ", namespace: r" + std::to_string(r.id) +
            ", kind: ground, start: [" + std::to_string(r.start.x) + ", " +
            std::to_string(r.start.y) + ", 0, " + std::to_string(r.start.yaw_deg) + "]}\n";
    for (const Pose4& g : r.goals)
      tours += (tours.empty() ? "" : ", ") + std::to_string(r.id) + ", " + std::to_string(g.x) +
               ", " + std::to_string(g.y) + ", " + std::to_string(g.z) + ", " +
               std::to_string(g.yaw_deg);
  }
  // the parameters of launch_cfg/explore_arena_team.yaml (table 5.3); the depth mask keeps
  // teammates out of the maps (thesis 5.2.2)
  return text + R"(remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params: {scene: )" +
         scene + R"(, seed: 1, publish_stereo: false, ground_camera_rate_hz: 5}
  - name: mask
    type: depth_mask
    params: {margin_m: 0.1}
  - name: mapper
    type: tsdf_mapper
    remap: {depth: depth_masked}
    params: {mode: single, voxel_m: 0.1, truncation_m: 0.3, w_th: 0.3, min_range_m: 0.3,
             max_range_m: 5.0, snapshot_every: 5}
  - name: low_level
    type: low_level_planner
    params: {)" +
         low_level_with_defaults(low_level_params) + R"(}
  - name: tracker
    type: path_tracker
    params: {ground_max_speed_mps: 0.5}
  - {name: log, type: test_robot_log}
  - {name: tours, type: test_tour_feeder, per_robot: false, params: {tours: [)" +
         tours + R"(]}}
  - {name: probe, type: test_pose_probe, per_robot: false}
)";
}

Outcome run_scenario(const std::string& scene, const std::vector<RobotSetup>& robots,
                     double duration_s, const std::string& low_level_params) {
  Outcome o;
  auto launch = Launch::from_string(launch_text(scene, robots, duration_s, low_level_params),
                                    "scenario.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  if (!launch) return o;
  o.launch = std::move(launch).value();
  const auto* sim = o.launch->find_component<team_simulator::TeamSimulator>();
  auto* probe = o.launch->find_component<PoseProbe>();
  EXPECT_NE(sim, nullptr);
  EXPECT_NE(probe, nullptr);
  if (sim == nullptr || probe == nullptr) return o;
  probe->sim = sim;
  o.probe = probe;
  for (const RobotSetup& r : robots)
    for (const auto& c : o.launch->components()) {
      if (c->robot_id() != r.id) continue;
      if (const auto* p = dynamic_cast<const LowLevelPlanner*>(c.get())) o.planners.push_back(p);
      if (const auto* t = dynamic_cast<const path_tracker::PathTracker*>(c.get()))
        o.trackers.push_back(t);
      if (const auto* l = dynamic_cast<const RobotLog*>(c.get())) o.logs.push_back(l);
    }
  EXPECT_EQ(o.planners.size(), robots.size());
  EXPECT_EQ(o.trackers.size(), robots.size());
  EXPECT_EQ(o.logs.size(), robots.size());
  if (o.planners.size() != robots.size() || o.trackers.size() != robots.size()) return o;
  o.launch->set_stop_condition([&o, &robots] {
    for (size_t i = 0; i < robots.size(); ++i)
      if (o.planners[i]->stats().goals_reached < robots[i].goals.size() ||
          o.planners[i]->mode() != Mode::kIdle || o.trackers[i]->mode() != Mode::kDone)
        return false;
    return true;
  });
  o.ran_s = o.launch->run();
  o.contacts = sim->simulator()->contacts();
  return o;
}

void expect_all_reached(const Outcome& o, const std::vector<RobotSetup>& robots, const char* name) {
  ASSERT_FALSE(o.probe->frames.empty());
  const PoseProbe::Frame& last = o.probe->frames.back();
  for (size_t i = 0; i < robots.size(); ++i) {
    const LowLevelPlanner::Stats& s = o.planners[i]->stats();
    EXPECT_EQ(s.goals_reached, robots[i].goals.size()) << name << " robot " << robots[i].id;
    EXPECT_EQ(s.goals_skipped, 0u) << name << " robot " << robots[i].id;
    EXPECT_EQ(o.planners[i]->mode(), Mode::kIdle) << name << " robot " << robots[i].id;
    EXPECT_EQ(o.trackers[i]->mode(), Mode::kDone) << name << " robot " << robots[i].id;
    const double error_m = distance_to(last.poses[i], robots[i].goals.back());
    EXPECT_LT(error_m, 0.1 + 1e-3) << name << " robot " << robots[i].id;
    std::printf(
        "[figures] %s: robot %u done at %.1f s, %.3f m from its goal, %.2f m travelled, %llu "
        "paths, %llu traffic holds, %llu emergency stops, %llu back-offs, %llu replanning "
        "requests, planning %.1f ms mean / %.1f ms max\n",
        name, robots[i].id, seconds(o.trackers[i]->done_stamp_ns()), error_m, s.path_length_m,
        static_cast<unsigned long long>(s.paths), static_cast<unsigned long long>(s.traffic_holds),
        static_cast<unsigned long long>(s.emergency_stops),
        static_cast<unsigned long long>(s.backoffs), static_cast<unsigned long long>(s.replans),
        s.paths + s.plan_failures > 0
            ? s.plan_ms_sum / static_cast<double>(s.paths + s.plan_failures)
            : 0.0,
        s.plan_ms_max);
  }
}

PathTally check_paths(const Truth& truth, const Outcome& o) {
  PathTally tally;
  PlannerConfig bare;  // the ground robot of table 5.3 (the launch's kind)
  bare.body_margin_m = 0;
  PlannerConfig strict;  // the planner's own body, unknown space occupied
  strict.unknown_is_occupied = true;
  for (const RobotLog* log : o.logs)
    for (const RobotLog::Path& p : log->paths) {
      ++tally.paths;
      const PathCheck check = truth.geometry.check_path(bare, body_of(bare), p.waypoints, 0.02);
      tally.samples += check.samples;
      if (check.colliding == 0) continue;
      ++tally.colliding;
      // where does it touch: resample and ask a planner that takes unknown space as occupied
      // on the map of the time whether each colliding pose lay in known free space
      bool known_free = false;
      if (p.map != nullptr) {
        auto planner = MotionPlanner::create(strict);
        EXPECT_TRUE(planner);
        if (!planner) continue;
        planner->update_map(p.map, p.map_stamp_ns);
        for (size_t i = 1; i < p.waypoints.size() && !known_free; ++i) {
          const msg::Waypoint& a = p.waypoints[i - 1];
          const msg::Waypoint& b = p.waypoints[i];
          const double length =
              std::hypot(b.position.x - a.position.x, b.position.y - a.position.y);
          const int n = std::max(1, static_cast<int>(std::ceil(length / 0.02)));
          for (int k = 0; k <= n && !known_free; ++k) {
            const double t = static_cast<double>(k) / n;
            msg::Waypoint w = a;
            w.position.x += t * (b.position.x - a.position.x);
            w.position.y += t * (b.position.y - a.position.y);
            w.yaw_rad = a.yaw_rad + t * std::remainder(b.yaw_rad - a.yaw_rad, 2 * M_PI);
            known_free =
                truth.geometry.collides(body_of(bare), body_pose(bare, w)) && planner->is_free(w);
          }
        }
      }
      if (known_free) ++tally.colliding_in_known_free;
      std::printf(
          "[figures] path %llu sent at %.1f s (%zu waypoints, from %.2f, %.2f): %zu of %zu "
          "samples touch the truth, first at %.2f, %.2f; %s\n",
          static_cast<unsigned long long>(p.plan_id), p.t_s, p.waypoints.size(),
          p.waypoints.front().position.x, p.waypoints.front().position.y, check.colliding,
          check.samples, check.first_colliding.position.x, check.first_colliding.position.y,
          known_free ? "IN KNOWN FREE SPACE" : "only where the map had no free space");
    }
  return tally;
}

Separation min_separation(const PoseProbe& probe) {
  Separation s;
  for (const PoseProbe::Frame& f : probe.frames)
    for (size_t i = 0; i < f.poses.size(); ++i)
      for (size_t k = i + 1; k < f.poses.size(); ++k) {
        const double d = (f.poses[i].head<2>() - f.poses[k].head<2>()).norm();
        if (d < s.centre_m) {
          s.centre_m = d;
          s.t_s = f.t_s;
          s.gap_m = gap(footprint(f.poses[i]), footprint(f.poses[k]));
        }
      }
  return s;
}

const Eigen::Vector3d* pose_at(const PoseProbe& probe, size_t i, double t_s) {
  for (const PoseProbe::Frame& f : probe.frames)
    if (f.t_s >= t_s - 1e-9) return &f.poses[i];
  return nullptr;
}

void expect_apart_and_clear_of_the_truth(const char* name, const std::string& scene,
                                         const Outcome& o) {
  const Separation sep = min_separation(*o.probe);
  EXPECT_GT(sep.centre_m, 0.6);
  EXPECT_GT(sep.gap_m, 0.0);
  const Truth truth = load_truth(scene);
  const PathTally paths = check_paths(truth, o);
  EXPECT_GE(paths.paths, 2u);
  EXPECT_EQ(paths.colliding, 0u);
  std::printf(
      "[figures] %s: min separation %.3f m centre to centre (footprint gap %.3f m) at "
      "%.1f s; ran %.1f s; %zu paths, %zu samples, %zu touching the truth\n",
      name, sep.centre_m, sep.gap_m, sep.t_s, o.ran_s, paths.paths, paths.samples, paths.colliding);
}

}  // namespace scancrew::low_level_planner::scenario_harness
