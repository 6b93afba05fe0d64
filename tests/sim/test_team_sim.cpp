// Physics, actuation, IMU, contacts, determinism and bad input of the team simulator
// (no rendering needed).

#include <gtest/gtest.h>

#include <cmath>

#include "tests/sim/sim_fixtures.hpp"

namespace scancrew::sim {
namespace {

using test::ground_robot;
using test::make_sim;
using test::multirotor;
using test::wall_scene;

constexpr int64_t kSecond = 1'000'000'000;

double yaw_of(const msg::Quat& q) {
  return std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
}

msg::VelocityCommand command(double vx, double vy, double vz, double yaw_rate) {
  msg::VelocityCommand c;
  c.linear_mps = {vx, vy, vz};
  c.yaw_rate_radps = yaw_rate;
  return c;
}

TEST(TeamSim, ImuAtRestReadsGravity) {
  auto sim = make_sim(wall_scene(), {ground_robot("r1", 0, 0)}, false);
  ASSERT_TRUE(sim);
  double ax = 0, ay = 0, az = 0, gz = 0;
  const int n = 200;
  for (int i = 0; i < n; ++i) {
    sim->step_until(sim->time_ns() + 10'000'000);
    const msg::Imu imu = sim->imu(0);
    ax += imu.linear_acceleration_mps2.x;
    ay += imu.linear_acceleration_mps2.y;
    az += imu.linear_acceleration_mps2.z;
    gz += imu.angular_velocity_radps.z;
  }
  EXPECT_NEAR(ax / n, 0.0, 0.01);
  EXPECT_NEAR(ay / n, 0.0, 0.01);
  EXPECT_NEAR(az / n, 9.81, 0.01);
  EXPECT_NEAR(gz / n, 0.0, 0.001);
}

TEST(TeamSim, GroundRobotDrivesAndTurnsAsCommanded) {
  auto sim = make_sim(wall_scene(), {ground_robot("r1", -2, 0)}, false);
  ASSERT_TRUE(sim);
  sim->set_velocity(0, command(0.5, 0.3 /*ignored: no sideways motion*/, 0, 0));
  sim->step_until(2 * kSecond);
  msg::Pose3 p = sim->body_pose(0);
  EXPECT_NEAR(p.position.x, -2 + 1.0, 0.01);
  EXPECT_NEAR(p.position.y, 0.0, 1e-6);
  sim->set_velocity(0, command(0, 0, 0, 0.5));
  sim->step_until(4 * kSecond);
  p = sim->body_pose(0);
  EXPECT_NEAR(yaw_of(p.orientation), 1.0, 0.01);
  EXPECT_NEAR(p.position.x, -1.0, 0.01);  // turning in place
  sim->set_velocity(0, command(0.5, 0, 0, 0));
  sim->step_until(6 * kSecond);
  p = sim->body_pose(0);
  EXPECT_NEAR(p.position.x, -1.0 + std::cos(1.0), 0.02);  // forward is along the heading
  EXPECT_NEAR(p.position.y, std::sin(1.0), 0.02);
}

TEST(TeamSim, MultirotorMovesInFourDegreesOfFreedom) {
  auto sim = make_sim(wall_scene(), {multirotor("uav", 0, 0, 1.5)}, false);
  ASSERT_TRUE(sim);
  sim->set_velocity(0, command(0.4, -0.2, 0.3, 0.0));
  sim->step_until(kSecond);
  const msg::Pose3 p = sim->body_pose(0);
  EXPECT_NEAR(p.position.x, 0.4, 0.01);
  EXPECT_NEAR(p.position.y, -0.2, 0.01);
  EXPECT_NEAR(p.position.z, 1.8, 0.01);
}

TEST(TeamSim, CommandsAreClampedToTwiceTheNominalSpeed) {
  auto sim = make_sim(wall_scene(), {ground_robot("r1", -2, 0)}, false);
  ASSERT_TRUE(sim);
  sim->set_velocity(0, command(50, 0, 0, 0));
  sim->step_until(kSecond);
  EXPECT_NEAR(sim->body_pose(0).position.x, -2 + 1.0, 0.02);
}

TEST(TeamSim, CountsRobotSceneAndRobotRobotContacts) {
  // a faces the wall 0.68 m ahead; b and c face each other 2 m apart
  auto sim = make_sim(wall_scene(),
                      {ground_robot("a", 2.0, 0), ground_robot("b", 0, 1.0, -M_PI_2),
                       ground_robot("c", 0, -1.0, M_PI_2)},
                      false);
  ASSERT_TRUE(sim);
  sim->step_until(kSecond);
  EXPECT_EQ(sim->contacts().robot_scene, 0u);
  EXPECT_EQ(sim->contacts().robot_robot, 0u);
  sim->set_velocity(0, command(0.5, 0, 0, 0));
  sim->set_velocity(1, command(0.5, 0, 0, 0));
  sim->step_until(5 * kSecond);
  // one onset each, though MuJoCo gives a box against a box several contact points
  EXPECT_EQ(sim->contacts().robot_scene, 1u);
  EXPECT_EQ(sim->contacts().robot_robot, 1u);
  const std::vector<ContactOnset> onsets = sim->take_contact_onsets();
  ASSERT_EQ(onsets.size(), 2u);
  for (const ContactOnset& o : onsets) {
    EXPECT_GT(o.t_s, 1.0);
    if (o.robot == 0) {
      EXPECT_EQ(o.other, "wall");
      EXPECT_NEAR(o.position.x, 2.9, 0.02);  // the wall's near face
      EXPECT_NEAR(o.robot_xy_yaw.x, 2.9 - 0.22, 0.03);
    } else {
      EXPECT_EQ(o.robot, 1u);  // b drives into c
      EXPECT_EQ(o.other, "c");
    }
  }
  EXPECT_TRUE(sim->take_contact_onsets().empty());  // taken
  // pushing on does not count the same contact again
  const ContactCounts before = sim->contacts();
  sim->step_until(6 * kSecond);
  EXPECT_EQ(sim->contacts().robot_scene, before.robot_scene);
  EXPECT_EQ(sim->contacts().robot_robot, before.robot_robot);
}

TEST(TeamSim, TwoRunsWithTheSameSeedGiveIdenticalTrajectories) {
  const auto run = [](uint64_t seed) {
    auto sim =
        make_sim(wall_scene(), {ground_robot("a", -3, 0), multirotor("u", 0, 2, 1)}, false, seed);
    std::vector<double> trace;
    for (int k = 0; k < 100; ++k) {
      sim->set_velocity(0, command(0.5 * std::sin(k * 0.1), 0, 0, 0.3 * std::cos(k * 0.07)));
      sim->set_velocity(1, command(0.2, 0.1 * std::sin(k * 0.2), 0.05, 0.1));
      sim->step_until(sim->time_ns() + 50'000'000);
      for (size_t r = 0; r < 2; ++r) {
        const auto p = sim->body_pose(r);
        const auto imu = sim->imu(r);
        trace.insert(trace.end(), {p.position.x, p.position.y, p.position.z, p.orientation.z,
                                   imu.linear_acceleration_mps2.x, imu.angular_velocity_radps.z});
      }
    }
    return trace;
  };
  const auto a = run(7), b = run(7), c = run(8);
  EXPECT_EQ(a, b);  // bitwise
  EXPECT_NE(a, c);  // the seed drives the IMU noise
}

TEST(TeamSim, RefusesARobotStartingInsideAnObstacle) {
  TeamSimConfig config;
  config.rendering = false;
  auto sim = TeamSim::create(wall_scene(), {ground_robot("r1", 3.0, 0)}, config);
  ASSERT_FALSE(sim);
  EXPECT_NE(sim.error().find("r1 starts inside 'wall'"), std::string::npos) << sim.error();
}

TEST(TeamSim, RefusesAnInvalidCamera) {
  TeamSimConfig config;
  config.rendering = false;
  auto robot = ground_robot("r1", 0, 0);
  robot.camera.baseline_m = 0;
  auto sim = TeamSim::create(wall_scene(), {robot}, config);
  ASSERT_FALSE(sim);
  EXPECT_NE(sim.error().find("baseline"), std::string::npos) << sim.error();
  robot.camera.baseline_m = 0.26;
  robot.camera.width = 320;
  robot.camera.height = 240;  // 90 x 60 degrees needs 320 x 185
  sim = TeamSim::create(wall_scene(), {robot}, config);
  ASSERT_FALSE(sim);
  EXPECT_NE(sim.error().find("for this width use height 185"), std::string::npos) << sim.error();
}

TEST(TeamSim, RefusesAStartOutsideTheBounds) {
  TeamSimConfig config;
  config.rendering = false;
  auto sim = TeamSim::create(wall_scene(), {ground_robot("r1", 9, 0)}, config);
  ASSERT_FALSE(sim);
  EXPECT_NE(sim.error().find("outside the scene bounds"), std::string::npos) << sim.error();
}

}  // namespace
}  // namespace scancrew::sim
