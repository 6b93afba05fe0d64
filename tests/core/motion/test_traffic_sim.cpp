// TrafficPolicy in closed loop (thesis 3.5.2): small deterministic kinematic simulations
// (kinematic_sim.hpp) of two to four robots. The figures printed with [figures] are the
// ones quoted in docs/traffic_policy.md.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "tests/core/motion/kinematic_sim.hpp"

namespace scancrew::motion::test {
namespace {

constexpr double kBodyRadiusM = 0.3;  // holds the 0.44 x 0.40 m ground robot
constexpr double kPi = std::numbers::pi;

// A corridor along x, |y| <= half_width: the body (a disc) must fit.
FreeSpaceQuery corridor(double half_width_m, double x_min = -100, double x_max = 100) {
  return [=](const Eigen::Vector3d& p) {
    return std::abs(p.y()) + kBodyRadiusM <= half_width_m + 1e-9 && p.x() >= x_min &&
           p.x() <= x_max;
  };
}
FreeSpaceQuery open_space() {
  return [](const Eigen::Vector3d&) { return true; };
}

TrafficConfig ground() {
  return TrafficConfig::for_kind(RobotKind::kGround);
}

void print(const char* name, const SimOutcome& o, const std::vector<SimRobot>& robots, double dt) {
  std::printf("[figures] %s: min separation %.3f m, ticks %d (%.1f s)", name, o.min_separation_m,
              o.ticks, o.ticks * dt);
  for (const SimRobot& r : robots)
    std::printf("; robot %u goal %.1f s, held %.1f s, aside %.1f s, travelled %.2f m", r.agent.id,
                r.goal_tick * dt, r.stop_ticks * dt, r.aside_ticks * dt, r.travelled_m);
  std::printf("\n");
}

TEST(TrafficSim, TwoGroundRobotsHeadOnInACorridorPassWithoutContact) {
  // a 2.4 m wide corridor, 10 m apart, nose to nose
  std::vector<SimRobot> robots;
  robots.emplace_back(1, RobotKind::kGround, Eigen::Vector3d(0, 0, 0), 0.0,
                      std::vector<Eigen::Vector3d>{{10, 0, 0}}, ground());
  robots.emplace_back(2, RobotKind::kGround, Eigen::Vector3d(10, 0, 0), kPi,
                      std::vector<Eigen::Vector3d>{{0, 0, 0}}, ground());
  const SimLimits lim;
  const SimOutcome o = run(robots, corridor(1.2), 1200, lim);
  print("head-on corridor 2.4 m", o, robots, lim.dt_s);

  ASSERT_TRUE(o.all_done) << "both reach their goals within 60 s";
  EXPECT_GT(o.min_separation_m, 2 * kBodyRadiusM) << "no contact";
  // the lower id keeps its lane, the other steps aside into free space and comes back
  EXPECT_FALSE(robots[0].stepped_aside);
  EXPECT_TRUE(robots[1].stepped_aside);
  EXPECT_GE(robots[1].resumes, 1);
  EXPECT_EQ(robots[0].replan_requests + robots[1].replan_requests, 0);
  // bounded detour: 10 m at 0.5 m/s is 20 s alone
  EXPECT_LT(robots[0].goal_tick * lim.dt_s, 30.0);
  EXPECT_LT(robots[1].goal_tick * lim.dt_s, 40.0);
}

TEST(TrafficSim, HeadOnWithSwappedIdsStepsAsideTheHigherIdToo) {
  std::vector<SimRobot> robots;
  robots.emplace_back(7, RobotKind::kGround, Eigen::Vector3d(0, 0, 0), 0.0,
                      std::vector<Eigen::Vector3d>{{10, 0, 0}}, ground());
  robots.emplace_back(3, RobotKind::kGround, Eigen::Vector3d(10, 0.1, 0), kPi,
                      std::vector<Eigen::Vector3d>{{0, 0.1, 0}}, ground());
  const SimOutcome o = run(robots, corridor(1.2), 1200);
  ASSERT_TRUE(o.all_done);
  EXPECT_GT(o.min_separation_m, 2 * kBodyRadiusM);
  EXPECT_TRUE(robots[0].stepped_aside);
  EXPECT_FALSE(robots[1].stepped_aside);
}

TEST(TrafficSim, ACrossingRobotWaitsThenProceeds) {
  // symmetric crossing: same distance, same speed; the tie goes to the lower id
  std::vector<SimRobot> robots;
  robots.emplace_back(1, RobotKind::kGround, Eigen::Vector3d(-6, 0, 0), 0.0,
                      std::vector<Eigen::Vector3d>{{6, 0, 0}}, ground());
  robots.emplace_back(2, RobotKind::kGround, Eigen::Vector3d(0, -6, 0), kPi / 2,
                      std::vector<Eigen::Vector3d>{{0, 6, 0}}, ground());
  const SimLimits lim;
  const SimOutcome o = run(robots, open_space(), 1200, lim);
  print("symmetric crossing", o, robots, lim.dt_s);
  ASSERT_TRUE(o.all_done);
  EXPECT_GT(o.min_separation_m, 2 * kBodyRadiusM + ground().margin_m);
  EXPECT_EQ(robots[0].stop_ticks, 0) << "robot 1 never waits";
  EXPECT_TRUE(robots[1].waited_for_crossing);
  EXPECT_GT(robots[1].stop_ticks, 0);
  EXPECT_GE(robots[1].resumes, 1);
  EXPECT_FALSE(robots[1].stepped_aside) << "it stopped before the crossing";
  EXPECT_EQ(robots[1].replan_requests, 0);
}

TEST(TrafficSim, TheLaterArrivalWaitsAtACrossingWhateverItsId) {
  // robot 1 is 2 m farther from the crossing: it waits for robot 2
  std::vector<SimRobot> robots;
  robots.emplace_back(1, RobotKind::kGround, Eigen::Vector3d(-8, 0, 0), 0.0,
                      std::vector<Eigen::Vector3d>{{6, 0, 0}}, ground());
  robots.emplace_back(2, RobotKind::kGround, Eigen::Vector3d(0, -6, 0), kPi / 2,
                      std::vector<Eigen::Vector3d>{{0, 6, 0}}, ground());
  const SimOutcome o = run(robots, open_space(), 1200);
  ASSERT_TRUE(o.all_done);
  EXPECT_GT(o.min_separation_m, 2 * kBodyRadiusM);
  EXPECT_TRUE(robots[0].waited_for_crossing);
  EXPECT_EQ(robots[1].stop_ticks, 0);
}

TEST(TrafficSim, AFollowerKeepsItsDistanceBehindASlowerLeader) {
  TrafficConfig c = ground();
  std::vector<SimRobot> robots;
  robots.emplace_back(1, RobotKind::kGround, Eigen::Vector3d(0, 0, 0), 0.0,
                      std::vector<Eigen::Vector3d>{{10, 0, 0}}, c);
  robots.emplace_back(2, RobotKind::kGround, Eigen::Vector3d(2, 0, 0), 0.0,
                      std::vector<Eigen::Vector3d>{{14, 0, 0}}, c);
  robots[1].agent.nominal_speed_mps = 0.25;
  const SimLimits lim;
  const SimOutcome o = run(robots, open_space(), 2000, lim);
  print("follower behind a slower leader", o, robots, lim.dt_s);
  ASSERT_TRUE(o.all_done);
  EXPECT_GT(o.min_separation_m, 2 * kBodyRadiusM + c.margin_m);
  EXPECT_FALSE(robots[0].stepped_aside);
  EXPECT_GT(robots[0].stop_ticks, 0);
  EXPECT_EQ(robots[1].stop_ticks, 0);
}

TEST(TrafficSim, ARobotHoldingOnAnotherOnesPathStepsAside) {
  // robot 2 waits for a plan (no path) in the middle of robot 1's corridor
  std::vector<SimRobot> robots;
  robots.emplace_back(1, RobotKind::kGround, Eigen::Vector3d(0, 0, 0), 0.0,
                      std::vector<Eigen::Vector3d>{{10, 0, 0}}, ground());
  robots.emplace_back(2, RobotKind::kGround, Eigen::Vector3d(5, 0.2, 0), kPi / 2,
                      std::vector<Eigen::Vector3d>{}, ground());
  const SimLimits lim;
  const SimOutcome o = run(robots, corridor(1.5), 1200, lim);
  print("holding robot in the corridor", o, robots, lim.dt_s);
  ASSERT_TRUE(o.all_done);
  EXPECT_GT(o.min_separation_m, 2 * kBodyRadiusM);
  EXPECT_TRUE(robots[1].stepped_aside);
  EXPECT_GT(std::abs(robots[1].agent.position.y()), 0.8) << "it cleared the corridor";
  EXPECT_EQ(robots[0].replan_requests, 0);
}

TEST(TrafficSim, FourRobotsAtASymmetricJunctionAllGetThrough) {
  // four robots, one per arm, all crossing to the opposite arm; every pair is symmetric
  std::vector<SimRobot> robots;
  const double d = 6;
  const std::array<Eigen::Vector3d, 4> starts = {
      Eigen::Vector3d(-d, 0, 0), {0, -d, 0}, {d, 0, 0}, {0, d, 0}};
  for (uint32_t i = 0; i < 4; ++i)
    robots.emplace_back(i + 1, RobotKind::kGround, starts[i], i * kPi / 2,
                        std::vector<Eigen::Vector3d>{-starts[i]}, ground());
  const SimLimits lim;
  const SimOutcome o = run(robots, open_space(), 3000, lim);
  print("four-way junction", o, robots, lim.dt_s);
  ASSERT_TRUE(o.all_done) << "no deadlock";
  EXPECT_GT(o.min_separation_m, 2 * kBodyRadiusM);
}

TEST(TrafficSim, TwoMultirotorsHeadOnPassWithoutContact) {
  TrafficConfig c = TrafficConfig::for_kind(RobotKind::kMultirotor);
  std::vector<SimRobot> robots;
  robots.emplace_back(1, RobotKind::kMultirotor, Eigen::Vector3d(0, 0, 2), 0.0,
                      std::vector<Eigen::Vector3d>{{12, 0, 2}}, c);
  robots.emplace_back(2, RobotKind::kMultirotor, Eigen::Vector3d(12, 0, 2), kPi,
                      std::vector<Eigen::Vector3d>{{0, 0, 2}}, c);
  for (SimRobot& r : robots) r.agent.body_radius_m = 0.4;  // 0.5 x 0.5 m frame
  const SimLimits lim;
  const SimOutcome o = run(robots, open_space(), 1500, lim);
  print("multirotors head-on", o, robots, lim.dt_s);
  ASSERT_TRUE(o.all_done);
  EXPECT_GT(o.min_separation_m, 0.8);
  EXPECT_TRUE(robots[1].stepped_aside);
}

TEST(TrafficSim, ANarrowCorridorEndsInReplanningRequestsNotAnEndlessWait) {
  // 1.0 m wide: no room to step aside; both hold, without contact, and both ask for a
  // new plan once max_wait_s has passed
  TrafficConfig c = ground();
  c.max_wait_s = 10;
  std::vector<SimRobot> robots;
  robots.emplace_back(1, RobotKind::kGround, Eigen::Vector3d(0, 0, 0), 0.0,
                      std::vector<Eigen::Vector3d>{{10, 0, 0}}, c);
  robots.emplace_back(2, RobotKind::kGround, Eigen::Vector3d(10, 0, 0), kPi,
                      std::vector<Eigen::Vector3d>{{0, 0, 0}}, c);
  const SimLimits lim;
  const SimOutcome o = run(robots, corridor(0.5), 600, lim);
  print("narrow corridor (no aside room)", o, robots, lim.dt_s);
  EXPECT_FALSE(o.all_done);
  EXPECT_GT(o.min_separation_m, 2 * kBodyRadiusM);
  EXPECT_EQ(robots[0].replan_requests, 1);
  EXPECT_EQ(robots[1].replan_requests, 1);
}

}  // namespace
}  // namespace scancrew::motion::test
