// Closed-loop traffic scenarios between teammates in the MuJoCo team simulator (step 7's
// "done when"; the harness: traffic_scenario_harness.hpp):
//   - head-on in a 3 m corridor: both robots reach their goals, a traffic maneuver was
//     issued, no contact;
//   - crossing at right angles, timed to meet: one robot stops while the other passes;
//   - an idle robot parked in the way steps aside;
//   - in every scenario, every local path is checked against the scene's true geometry
//     (the body without the margin, every 2 cm): none collides where the map showed free
//     space.
// The figures printed with [figures] are the ones quoted in docs/traffic_policy.md.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/components/low_level_planner/traffic_scenario_harness.hpp"

namespace scancrew::low_level_planner {
namespace {

using namespace scenario_harness;  // NOLINT(google-build-using-namespace): the harness

TEST(TrafficScenarios, TwoGroundRobotsHeadOnInACorridorPassWithoutContact) {
  // 9 m apart nose to nose in a 3 m wide corridor; each goal is the other's start
  const std::vector<RobotSetup> robots = {{1, {-4.5, 0, 0, 0}, {{4.5, 0, 0, 0}}},
                                          {2, {4.5, 0, 0, 180}, {{-4.5, 0, 0, 180}}}};
  const std::string scene = scene_path("corridor.yaml");
  const Outcome o = run_scenario(scene, robots, 60.0);
  ASSERT_NE(o.probe, nullptr);
  ASSERT_EQ(o.logs.size(), 2u);
  expect_all_reached(o, robots, "head-on");
  EXPECT_EQ(o.contacts.robot_robot, 0u);
  EXPECT_EQ(o.contacts.robot_scene, 0u);
  // a traffic maneuver was issued, because of the teammate
  size_t holds = 0;
  for (size_t i = 0; i < 2; ++i)
    for (const RobotLog::Maneuver& m : o.logs[i]->maneuvers)
      if (is_traffic_hold(m)) {
        ++holds;
        EXPECT_EQ(m.because_of_robot, robots[1 - i].id);
        const Eigen::Vector3d* self = pose_at(*o.probe, i, m.t_s);
        const Eigen::Vector3d* other = pose_at(*o.probe, 1 - i, m.t_s);
        ASSERT_TRUE(self != nullptr && other != nullptr);
        std::printf("[figures] head-on: robot %u %s at %.1f s, %.2f m from robot %u\n",
                    robots[i].id, m.kind == ManeuverKind::kStop ? "stops" : "steps aside", m.t_s,
                    (self->head<2>() - other->head<2>()).norm(), robots[1 - i].id);
      }
  EXPECT_GE(holds, 1u);
  // frontal: the lower id keeps its lane, the other steps aside
  EXPECT_EQ(o.planners[0]->stats().traffic_holds, 0u);
  EXPECT_TRUE(std::any_of(o.logs[1]->maneuvers.begin(), o.logs[1]->maneuvers.end(),
                          [](const RobotLog::Maneuver& m) {
                            return m.kind == ManeuverKind::kStepAside && m.because_of_robot == 1;
                          }));
  expect_apart_and_clear_of_the_truth("head-on", scene, o);
}

TEST(TrafficScenarios, ACrossingRobotWaitsWhileTheOtherPasses) {
  // perpendicular straight paths through the room's centre, both 4 m from it: they would
  // meet there
  const std::vector<RobotSetup> robots = {{1, {-4, 0, 0, 0}, {{4, 0, 0, 0}}},
                                          {2, {0, -4, 0, 90}, {{0, 4, 0, 90}}}};
  const std::string scene = scene_path("open_room.yaml");
  const Outcome o = run_scenario(scene, robots, 60.0);
  ASSERT_NE(o.probe, nullptr);
  ASSERT_EQ(o.logs.size(), 2u);
  expect_all_reached(o, robots, "crossing");
  EXPECT_EQ(o.contacts.robot_robot, 0u);
  EXPECT_EQ(o.contacts.robot_scene, 0u);
  // one robot stops because of the other, and the other crosses the centre line of the
  // waiting robot's path while it waits
  bool waited_while_passed = false;
  for (size_t i = 0; i < 2; ++i) {
    const auto& ms = o.logs[i]->maneuvers;
    for (size_t k = 0; k < ms.size(); ++k) {
      if (ms[k].kind != ManeuverKind::kStop || ms[k].because_of_robot == 0) continue;
      EXPECT_EQ(ms[k].because_of_robot, robots[1 - i].id);
      const double resume_s = k + 1 < ms.size() ? ms[k + 1].t_s : o.ran_s;
      // the other robot's coordinate across this robot's path (x for robot 2, y for robot 1)
      const int axis = i == 0 ? 1 : 0;
      const Eigen::Vector3d* at_stop = pose_at(*o.probe, 1 - i, ms[k].t_s);
      const Eigen::Vector3d* at_resume = pose_at(*o.probe, 1 - i, resume_s);
      ASSERT_NE(at_stop, nullptr);
      ASSERT_NE(at_resume, nullptr);
      const bool passed = (*at_stop)[axis] < 0 && (*at_resume)[axis] > 0;
      waited_while_passed = waited_while_passed || passed;
      const Eigen::Vector3d* waiter = pose_at(*o.probe, i, ms[k].t_s);
      std::printf(
          "[figures] crossing: robot %u stops at %.1f s, %.2f m from the crossing, resumes at "
          "%.1f s; robot %u crossed meanwhile: %s\n",
          robots[i].id, ms[k].t_s, waiter->head<2>().norm(), resume_s, robots[1 - i].id,
          passed ? "yes" : "no");
    }
  }
  EXPECT_TRUE(waited_while_passed);
  // a tie at the crossing (both 4 m from it): the lower id proceeds
  EXPECT_EQ(o.planners[0]->stats().traffic_holds, 0u);
  EXPECT_GE(o.planners[1]->stats().traffic_holds, 1u);
  expect_apart_and_clear_of_the_truth("crossing", scene, o);
}

TEST(TrafficScenarios, AnIdleRobotInTheWayStepsAside) {
  // robot 2 drives 2 m west, turns north and is idle there, parked mid-corridor on robot
  // 1's way (the planners' maps hold no teammate: depth_mask blanks it out)
  const std::vector<RobotSetup> robots = {{1, {-4.5, 0, 0, 0}, {{4.5, 0, 0, 0}}},
                                          {2, {2.5, 0, 0, 180}, {{0.5, 0, 0, 90}}}};
  const std::string scene = scene_path("corridor.yaml");
  const Outcome o = run_scenario(scene, robots, 60.0);
  ASSERT_NE(o.probe, nullptr);
  ASSERT_EQ(o.logs.size(), 2u);
  EXPECT_EQ(o.planners[0]->stats().goals_reached, 1u);
  EXPECT_EQ(o.trackers[0]->mode(), Mode::kDone);
  const PoseProbe::Frame& last = o.probe->frames.back();
  EXPECT_LT(distance_to(last.poses[0], robots[0].goals.back()), 0.1 + 1e-3);
  EXPECT_EQ(o.contacts.robot_robot, 0u);
  EXPECT_EQ(o.contacts.robot_scene, 0u);
  // the idle robot stepped aside because of robot 1, once, and stayed off robot 1's way
  const auto& ms = o.logs[1]->maneuvers;
  const auto aside = std::find_if(ms.begin(), ms.end(), [](const RobotLog::Maneuver& m) {
    return m.kind == ManeuverKind::kStepAside && m.because_of_robot == 1;
  });
  ASSERT_NE(aside, ms.end());
  EXPECT_EQ(o.planners[1]->stats().traffic_holds, 1u);
  EXPECT_GT(std::abs(last.poses[1].y()), 0.8);  // the clearance off the corridor's centre line
  std::printf("[figures] idle in the way: robot 2 steps aside at %.1f s, robot 1 done at %.1f s\n",
              aside->t_s, seconds(o.trackers[0]->done_stamp_ns()));
  expect_apart_and_clear_of_the_truth("idle in the way", scene, o);
}

}  // namespace
}  // namespace scancrew::low_level_planner
