// read_checks_config: the checks' keys from a launch_cfg mapping, thesis defaults per robot
// kind, and errors that name the key.

#include <gtest/gtest.h>

#include "components/low_level/checks_config.hpp"
#include "components/low_level/replan_request.hpp"
#include "executors/params.hpp"

namespace scancrew::low_level {
namespace {

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
      "safety_semi_major_m: 0.6\n"
      "safety_semi_minor_m: 0.3\n"
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
  EXPECT_DOUBLE_EQ(c.obstacle.semi_major_m, 0.6);
  EXPECT_DOUBLE_EQ(c.obstacle.semi_minor_m, 0.3);
  EXPECT_DOUBLE_EQ(c.traffic.d0_m, 0.7);
  EXPECT_DOUBLE_EQ(c.traffic.safety_distance_m(0.5), 1.45);
  EXPECT_DOUBLE_EQ(c.traffic.max_wait_s, 12);
  EXPECT_DOUBLE_EQ(c.redundancy.same_goal_distance_m, 0.4);
}

TEST(ChecksConfig, BadValuesAreReportedWithTheirKey) {
  ParamReader p = ParamReader::from_yaml_string(
      "c_thres_percent: 120\n"
      "safety_semi_major_m: 0.2\n",  // below the 0.25 m semi-minor axis
      "bad.yaml");
  (void)read_checks_config(p, RobotKind::kGround);
  ASSERT_FALSE(p.ok());
  std::string all;
  for (const std::string& e : p.errors()) all += e + "\n";
  EXPECT_NE(all.find("c_thres_percent"), std::string::npos) << all;
  EXPECT_NE(all.find("safety_semi_major_m"), std::string::npos) << all;
}

TEST(ReplanRequest, ReasonsHaveNames) {
  EXPECT_STREQ(to_string(ReplanReason::kUtility), "utility");
  EXPECT_STREQ(to_string(ReplanReason::kRedundancy), "redundancy");
  EXPECT_STREQ(to_string(ReplanReason::kTrafficStuck), "traffic_stuck");
  EXPECT_STREQ(to_string(RobotKind::kMultirotor), "multirotor");
}

}  // namespace
}  // namespace scancrew::low_level
