// read_checks_config and read_planner_config: the checks' and the planner's keys from a
// launch_cfg mapping, thesis defaults per robot kind, and errors that name the key.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "components/low_level_planner/planner_params.hpp"
#include "core/motion/checks_config.hpp"
#include "core/motion/motion_planner.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::low_level_planner {
namespace {

using motion::MotionPlanner;
using ReplanReason = msg::ReplanRequest::Reason;

TEST(ChecksConfig, DefaultsFollowTheThesisTablesPerRobotKind) {
  const ChecksConfig g = ChecksConfig::for_kind(RobotKind::kGround);
  EXPECT_DOUBLE_EQ(g.obstacle.semi_major_m, 0.55);  // table 5.3
  EXPECT_DOUBLE_EQ(g.obstacle.semi_minor_m, 0.25);
  EXPECT_DOUBLE_EQ(g.utility.c_thres_percent, 80.0);  // tables 2.1, 3.1, 4.1
  EXPECT_TRUE(g.redundancy.planar);
  const ChecksConfig a = ChecksConfig::for_kind(RobotKind::kMultirotor);
  EXPECT_EQ(a.obstacle.kind, RobotKind::kMultirotor);
  EXPECT_DOUBLE_EQ(a.obstacle.sphere_radius_m, 1.0);  // tables 2.1, 3.1, 4.1
  EXPECT_DOUBLE_EQ(a.traffic.d0_m, 1.0);
  EXPECT_FALSE(a.redundancy.planar);
  EXPECT_TRUE(g.validate().empty());
  EXPECT_TRUE(a.validate().empty());
}

TEST(ChecksConfig, ReadsEveryKeyFromTheLaunchMapping) {
  ParamReader p = ParamReader::from_yaml_string(
      "goal_position_tolerance_m: 0.3\n"
      "goal_yaw_tolerance_deg: 20\n"
      "c_thres_percent: 50\n"
      "traffic_d0_m: 0.7\n"
      "traffic_k_s: 1.5\n"
      "traffic_max_wait_s: 12\n"
      "redundancy_same_goal_m: 0.4\n",
      "test.yaml");
  const ChecksConfig c = read_checks_config(p, RobotKind::kGround);
  p.finish();
  ASSERT_TRUE(p.ok()) << p.errors().front();
  EXPECT_DOUBLE_EQ(c.goal.position_tolerance_m, 0.3);
  EXPECT_DOUBLE_EQ(c.goal.yaw_tolerance_deg, 20);
  EXPECT_DOUBLE_EQ(c.utility.c_thres_percent, 50);
  EXPECT_DOUBLE_EQ(c.traffic.d0_m, 0.7);
  EXPECT_DOUBLE_EQ(c.traffic.safety_distance_m(0.5), 1.45);
  EXPECT_DOUBLE_EQ(c.traffic.max_wait_s, 12);
  EXPECT_DOUBLE_EQ(c.redundancy.same_goal_distance_m, 0.4);
}

TEST(ChecksConfig, BadValuesAreReportedWithTheirKey) {
  ParamReader p = ParamReader::from_yaml_string(
      "c_thres_percent: 120\n"
      "goal_yaw_tolerance_deg: 200\n",  // above 180
      "bad.yaml");
  (void)read_checks_config(p, RobotKind::kGround);
  ASSERT_FALSE(p.ok());
  std::string all;
  for (const std::string& e : p.errors()) all += e + "\n";
  EXPECT_NE(all.find("c_thres_percent"), std::string::npos) << all;
  EXPECT_NE(all.find("goal_yaw_tolerance_deg"), std::string::npos) << all;
}

TEST(ChecksConfig, TheSafetyVolumeIsTheBodyAndNoKeySizesIt) {
  // one body model (core/robot/body_model.hpp): table 5.3's 0.55 x 0.25 m ellipse for a ground
  // robot, table 2.1's 1 m sphere for a multirotor
  const ChecksConfig g = ChecksConfig::for_kind(RobotKind::kGround);
  const ChecksConfig a = ChecksConfig::for_kind(RobotKind::kMultirotor);
  EXPECT_DOUBLE_EQ(g.obstacle.semi_major_m, 0.55);
  EXPECT_DOUBLE_EQ(g.obstacle.semi_minor_m, 0.25);
  EXPECT_DOUBLE_EQ(a.obstacle.sphere_radius_m, 1.0);
  for (const char* key : {"safety_radius_m", "safety_semi_major_m", "ground_body_radii_m",
                          "multirotor_body_radius_m"}) {
    ParamReader p = ParamReader::from_yaml_string(std::string(key) + ": 0.6\n", "test.yaml");
    (void)read_checks_config(p, RobotKind::kGround);
    (void)read_planner_config(p);
    p.finish();
    ASSERT_EQ(p.errors().size(), 1U) << key;
    EXPECT_NE(p.errors().front().find("unknown parameter"), std::string::npos) << key;
  }
}

TEST(ReplanRequest, ReasonsHaveNames) {
  EXPECT_STREQ(to_string(ReplanReason::kUtility), "utility");
  EXPECT_STREQ(to_string(ReplanReason::kRedundancy), "redundancy");
  EXPECT_STREQ(to_string(ReplanReason::kTrafficStuck), "traffic_stuck");
  EXPECT_STREQ(to_string(RobotKind::kMultirotor), "multirotor");
}

TEST(PlannerConfig, ReadsTheKeysAndReportsBadValues) {
  ParamReader p = ParamReader::from_yaml_string(
      "robot_type: multirotor\n"
      "body_margin_m: 0.2\n"
      "unknown_is_occupied: false\n"
      "planner_time_limit_s: 0.25\n"
      "roadmap_max_vertices: 300\n",
      "test");
  const PlannerConfig c = read_planner_config(p);
  p.finish();
  ASSERT_TRUE(p.ok()) << p.errors().front();
  EXPECT_EQ(c.robot_kind, RobotKind::kMultirotor);
  EXPECT_FALSE(c.unknown_is_occupied);
  EXPECT_DOUBLE_EQ(c.planner_time_limit_s, 0.25);
  EXPECT_EQ(c.roadmap_max_vertices, 300);
  EXPECT_DOUBLE_EQ(body_of(c).safety_radii_m.x(), 1.0 + 0.2);  // table 2.1's sphere + margin

  ParamReader bad = ParamReader::from_yaml_string(
      "robot_type: boat\nplanner_time_limit_s: -1\nbody_margin_m: -1\n", "test");
  (void)read_planner_config(bad);
  EXPECT_GE(bad.errors().size(), 3u);

  PlannerConfig inverted;
  inverted.multirotor_min_altitude_m = 5;
  inverted.multirotor_max_altitude_m = 2;
  EXPECT_FALSE(MotionPlanner::create(inverted).has_value());
}

TEST(RoadmapDistances, ConfigKeysAndBadValues) {
  ParamReader p = ParamReader::from_yaml_string(
      "roadmap_distance_min_vertices: 120\nroadmap_distance_grow_time_s: 0.05\n", "test");
  const PlannerConfig c = read_planner_config(p);
  p.finish();
  ASSERT_TRUE(p.ok()) << p.errors().front();
  EXPECT_EQ(c.roadmap_distance_min_vertices, 120);
  EXPECT_DOUBLE_EQ(c.roadmap_distance_grow_time_s, 0.05);

  ParamReader bad = ParamReader::from_yaml_string("roadmap_distance_min_vertices: -5\n", "test");
  (void)read_planner_config(bad);
  ASSERT_FALSE(bad.errors().empty());
  EXPECT_NE(bad.errors().front().find("roadmap_distance_min_vertices"), std::string::npos)
      << bad.errors().front();
  ParamReader negative =
      ParamReader::from_yaml_string("roadmap_distance_grow_time_s: -1\n", "test");
  (void)read_planner_config(negative);
  EXPECT_FALSE(negative.errors().empty());
  PlannerConfig direct;
  direct.roadmap_distance_grow_time_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(MotionPlanner::create(direct).has_value());
  direct.roadmap_distance_grow_time_s = 0.1;
  direct.roadmap_distance_min_vertices = -1;
  EXPECT_FALSE(MotionPlanner::create(direct).has_value());
}

}  // namespace
}  // namespace scancrew::low_level_planner
