// Closed-loop scenarios against the scene in the MuJoCo team simulator (step 7's "done
// when"; the harness: traffic_scenario_harness.hpp):
//   - a goal in collision moves to a free pose near it;
//   - emergency stop: a robot plans straight through unknown space towards a goal behind a
//     box it has not seen; ObstacleCheck stops it clear of the box, it goes round; with the
//     path re-check, a newer map blocks the path and the robot plans round before any stop;
//   - a goal whose way grows past the detour budget is skipped;
//   - a robot shut in with no path out backs off farther at each round, then gives up;
//   - every local path is checked against the scene's true geometry (the body without the
//     margin, every 2 cm): none collides where the map showed free space.
// The figures printed with [figures] are the ones quoted in docs/traffic_policy.md.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "tests/components/low_level_planner/traffic_scenario_harness.hpp"

namespace scancrew::low_level_planner {
namespace {

using namespace scenario_harness;  // NOLINT(google-build-using-namespace): the harness

TEST(TrafficScenarios, AGoalInCollisionMovesToAFreePoseNearIt) {
  // the goal faces the corridor's north wall from 0.45 m: the safety ellipse's 0.55 m
  // semi-major axis overlaps it; the goal moves to the nearest free pose within 0.3 m
  const std::vector<RobotSetup> robots = {{1, {-4.5, 0, 0, 0}, {{0, 1.05, 0, 90}}}};
  const std::string scene = scene_path("corridor.yaml");
  const Outcome o = run_scenario(scene, robots, 40.0);
  ASSERT_NE(o.probe, nullptr);
  ASSERT_EQ(o.planners.size(), 1u);
  const LowLevelPlanner::Stats& s = o.planners[0]->stats();
  EXPECT_EQ(s.goals_reached, 1u);
  EXPECT_EQ(s.goals_skipped, 0u);
  EXPECT_GE(s.goals_nudged, 1u);
  const double error_m = distance_to(o.probe->frames.back().poses[0], robots[0].goals.back());
  EXPECT_GT(error_m, 0.05);       // not at the goal in collision...
  EXPECT_LT(error_m, 0.3 + 0.1);  // ...but within the nudge and the tracker's tolerance
  EXPECT_EQ(o.contacts.robot_scene, 0u);
  std::printf("[figures] goal in collision: reached %.2f m from it, %llu nudges\n", error_m,
              static_cast<unsigned long long>(s.goals_nudged));
}

TEST(TrafficScenarios, TheEmergencyStopFiresBeforeAnUnseenBoxAndTheRobotGoesRound) {
  // facing away from the box; the goal lies behind it. Without the path re-check (the
  // thesis's behaviour), which would plan round the box before the check fires (next test)
  const std::vector<RobotSetup> robots = {{1, {0, 0, 0, 180}, {{3.2, 0, 0, 0}}}};
  const std::string scene = scene_path("box_behind.yaml");
  const Outcome o = run_scenario(scene, robots, 60.0, "path_recheck_horizon_m: 0");
  ASSERT_NE(o.probe, nullptr);
  ASSERT_EQ(o.logs.size(), 1u);
  const Truth truth = load_truth(scene);
  ASSERT_EQ(truth.scene.boxes.size(), 1u);
  const RobotLog& log = *o.logs[0];
  // the first path goes straight through the box: the map had not seen it
  ASSERT_FALSE(log.paths.empty());
  PlannerConfig bare;
  bare.body_margin_m = 0;
  EXPECT_GT(
      truth.geometry.check_path(bare, body_of(bare), log.paths.front().waypoints, 0.02).colliding,
      0u)
      << "the first path should cross the unseen box";
  // the emergency stop: a stop for no teammate, then a replanning request
  EXPECT_GE(o.planners[0]->stats().emergency_stops, 1u);
  const auto stop =
      std::find_if(log.maneuvers.begin(), log.maneuvers.end(), [](const RobotLog::Maneuver& m) {
        return m.kind == ManeuverKind::kStop && m.because_of_robot == 0;
      });
  ASSERT_NE(stop, log.maneuvers.end());
  const auto request =
      std::find_if(log.modes.begin(), log.modes.end(), [&](const std::pair<double, Mode>& m) {
        return m.first >= stop->t_s - 1e-9 && m.second == Mode::kPlanning;
      });
  ASSERT_NE(request, log.modes.end());
  EXPECT_LT(request->first - stop->t_s, 0.15);  // in the same tick (the state follows it)
  const Eigen::Vector3d* at_stop = pose_at(*o.probe, 0, stop->t_s);
  ASSERT_NE(at_stop, nullptr);
  const Rect& box = truth.solids.back();  // the box comes after the four walls
  const double gap_at_stop = gap(footprint(*at_stop), box);
  const double centre_to_face = box.center.x() - box.half.x() - at_stop->x();
  EXPECT_GT(gap_at_stop, 0.0);
  // clear of the box for the whole run, and no contact at all
  double min_gap = 1e300, min_gap_t = 0;
  for (const PoseProbe::Frame& f : o.probe->frames) {
    const double g = scene_gap(truth, f.poses[0]);
    if (g < min_gap) {
      min_gap = g;
      min_gap_t = f.t_s;
    }
  }
  EXPECT_GT(min_gap, 0.0);
  EXPECT_EQ(o.contacts.robot_scene, 0u);
  // then round the box to the goal
  expect_all_reached(o, robots, "emergency stop");
  const PathTally paths = check_paths(truth, o);
  EXPECT_EQ(paths.colliding_in_known_free, 0u);
  std::printf(
      "[figures] emergency stop at %.1f s: robot centre %.2f m from the box face, footprint gap "
      "%.3f m; smallest gap to the scene over the run %.3f m at %.1f s; ran %.1f s; %zu paths, "
      "%zu touching the truth, %zu of them in known free space\n",
      stop->t_s, centre_to_face, gap_at_stop, min_gap, min_gap_t, o.ran_s, paths.paths,
      paths.colliding, paths.colliding_in_known_free);
}

TEST(TrafficScenarios, ANewerMapBlocksThePathAndTheRobotPlansRoundTheBoxBeforeAnyStop) {
  // the scene of the emergency stop, with the path re-check (the default): once the box is
  // in a snapshot, the path through it is planned again, before the box is near enough for
  // ObstacleCheck
  const std::vector<RobotSetup> robots = {{1, {0, 0, 0, 180}, {{3.2, 0, 0, 0}}}};
  const std::string scene = scene_path("box_behind.yaml");
  const Outcome o = run_scenario(scene, robots, 60.0);
  ASSERT_NE(o.probe, nullptr);
  ASSERT_EQ(o.logs.size(), 1u);
  const Truth truth = load_truth(scene);
  const RobotLog& log = *o.logs[0];
  PlannerConfig bare;
  bare.body_margin_m = 0;
  ASSERT_FALSE(log.paths.empty());
  EXPECT_GT(
      truth.geometry.check_path(bare, body_of(bare), log.paths.front().waypoints, 0.02).colliding,
      0u)
      << "the first path should cross the unseen box";
  const LowLevelPlanner::Stats& s = o.planners[0]->stats();
  EXPECT_GE(s.paths_blocked, 1u);
  EXPECT_EQ(s.emergency_stops, 0u);
  EXPECT_GE(log.paths.size(), 2u);
  EXPECT_EQ(o.contacts.robot_scene, 0u);
  double min_gap = 1e300;
  for (const PoseProbe::Frame& f : o.probe->frames)
    min_gap = std::min(min_gap, scene_gap(truth, f.poses[0]));
  EXPECT_GT(min_gap, 0.0);
  expect_all_reached(o, robots, "path re-check");
  const PathTally paths = check_paths(truth, o);
  EXPECT_EQ(paths.colliding_in_known_free, 0u);
  std::printf(
      "[figures] path re-check: %llu paths blocked, %llu emergency stops, %zu paths; smallest "
      "gap to the scene %.3f m; ran %.1f s\n",
      static_cast<unsigned long long>(s.paths_blocked),
      static_cast<unsigned long long>(s.emergency_stops), log.paths.size(), min_gap, o.ran_s);
}

TEST(TrafficScenarios, AGoalWhoseWayGrowsPastTheDetourBudgetIsSkipped) {
  // the goal inside an unseen closed ring, 4 m away: each newer map blocks the way in, and
  // unknown space offers another round the ring. With the budget (factor 1, + the 1 m
  // re-check horizon: 5 m) the goal is skipped once the way passes it; without, the robot
  // goes on until the ring is mapped and the queries fail
  const std::vector<RobotSetup> robots = {{1, {0, 0, 0, 180}, {{4.0, 0, 0, 0}}}};
  const std::string scene = scene_path("ring.yaml");
  const std::string params = "path_recheck_horizon_m: 1, max_detour_factor: ";
  const Outcome with = run_scenario(scene, robots, 90.0, params + "1");
  const Outcome without = run_scenario(scene, robots, 90.0, params + "0");
  ASSERT_EQ(with.planners.size(), 1u);
  ASSERT_EQ(without.planners.size(), 1u);
  const LowLevelPlanner::Stats& w = with.planners[0]->stats();
  const LowLevelPlanner::Stats& n = without.planners[0]->stats();
  EXPECT_EQ(w.detours, 1u);
  EXPECT_EQ(w.goals_skipped, 1u);
  EXPECT_EQ(w.goals_reached, 0u);
  EXPECT_EQ(n.detours, 0u);
  EXPECT_EQ(n.goals_reached, 0u);
  EXPECT_GE(n.paths_blocked, 2u) << "the way round the ring should be blocked again and again";
  EXPECT_LT(w.path_length_m, n.path_length_m);
  // (without the budget, the robot probing round the ring in unknown space touches it)
  EXPECT_EQ(with.contacts.robot_scene, 0u);
  std::printf(
      "[figures] detour budget: with (factor 1): skipped after %.2f m, %llu paths, %llu blocked; "
      "without: %.2f m, %llu paths, %llu blocked, %llu goals skipped, %llu contacts\n",
      w.path_length_m, static_cast<unsigned long long>(w.paths),
      static_cast<unsigned long long>(w.paths_blocked), n.path_length_m,
      static_cast<unsigned long long>(n.paths), static_cast<unsigned long long>(n.paths_blocked),
      static_cast<unsigned long long>(n.goals_skipped),
      static_cast<unsigned long long>(without.contacts.robot_scene));
}

TEST(TrafficScenarios, ARobotWithNoPathOutBacksOffFartherAtEachRoundThenGivesUp) {
  // shut in a closet, its goals outside: once the walls are mapped every query fails
  // (timeout). Six goals: a round is max_consecutive_failures (3) failed queries
  std::vector<Pose4> outside;
  outside.reserve(6);
  for (int k = 0; k < 6; ++k) outside.push_back({4.0, -1.0 + 0.4 * k, 0, 0});
  const std::vector<RobotSetup> robots = {{1, {0, 0, 0, 0}, outside}};
  const std::string scene = scene_path("closet.yaml");
  const std::string params =
      "planner_time_limit_s: 0.05, backoff_max_m: 0.6, backoff_min_m: 0.2, "
      "path_recheck_horizon_m: 0";
  struct Run {
    LowLevelPlanner::Stats stats;
    double moved_m = 0;
  };
  const auto run = [&](const std::string& extra) {
    Run out;
    const Outcome o = run_scenario(scene, robots, 25.0, params + extra);
    EXPECT_NE(o.probe, nullptr);
    if (o.probe == nullptr || o.planners.empty()) return out;
    out.stats = o.planners[0]->stats();
    for (const PoseProbe::Frame& f : o.probe->frames)
      out.moved_m = std::max(out.moved_m, f.poses[0].head<2>().norm());
    EXPECT_EQ(o.contacts.robot_scene, 0u);
    return out;
  };
  const Run without = run("");
  const Run with = run(", stuck_backoff_m: 0.3");
  EXPECT_EQ(without.stats.stuck_backoffs, 0u);
  EXPECT_EQ(with.stats.goals_reached, 0u);
  // rounds at >= 0.3 m and >= 0.6 m; a third (0.9 m) would pass backoff_max_m
  EXPECT_EQ(with.stats.stuck_backoffs, 2u);
  EXPECT_GE(with.moved_m, 0.3);
  std::printf(
      "[figures] stuck in a closet: without stuck_backoff_m %llu failed queries, %llu goals "
      "skipped, moved %.2f m; with 0.3 m: %llu failed queries, %llu back-offs from the place, "
      "%llu goals skipped, moved %.2f m\n",
      static_cast<unsigned long long>(without.stats.plan_failures),
      static_cast<unsigned long long>(without.stats.goals_skipped), without.moved_m,
      static_cast<unsigned long long>(with.stats.plan_failures),
      static_cast<unsigned long long>(with.stats.stuck_backoffs),
      static_cast<unsigned long long>(with.stats.goals_skipped), with.moved_m);
}

}  // namespace
}  // namespace scancrew::low_level_planner
