// TrafficPolicy's rules one at a time (thesis 3.5.2 item 5): the pair verdict (encounter,
// priority) is the same from both robots, the safety distance grows with speed, and each
// maneuver (stop, step aside, resume, re-planning after a long hold) comes when it should.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/motion/traffic_policy.hpp"

namespace scancrew::motion {
namespace {

constexpr double kPi = std::numbers::pi;

TrafficAgent agent(uint32_t id, Eigen::Vector3d at, double yaw, std::vector<Eigen::Vector3d> path,
                   double speed = 0.5) {
  TrafficAgent a;
  a.id = id;
  a.position = at;
  a.yaw_rad = yaw;
  a.velocity_mps = Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0) * speed;
  a.path = std::move(path);
  return a;
}

const TrafficConfig kGround = TrafficConfig::for_kind(RobotKind::kGround);
FreeSpaceQuery anywhere() {
  return [](const Eigen::Vector3d&) { return true; };
}

void expect_same(const PairConflict& x, const PairConflict& y) {
  EXPECT_EQ(x.found, y.found);
  EXPECT_EQ(x.encounter, y.encounter);
  EXPECT_EQ(x.priority_id, y.priority_id);
  EXPECT_DOUBLE_EQ(x.s_first_m, y.s_first_m);
  EXPECT_DOUBLE_EQ(x.s_second_m, y.s_second_m);
}

TEST(PairConflict, HeadOnIsFrontalAndTheLowerIdProceedsFromBothSides) {
  const TrafficAgent a = agent(4, {0, 0, 0}, 0, {{10, 0, 0}});
  const TrafficAgent b = agent(2, {3, 0.2, 0}, kPi, {{-7, 0.2, 0}});
  const PairConflict ab = pair_conflict(a, b, kGround);
  ASSERT_TRUE(ab.found);
  EXPECT_EQ(ab.encounter, Encounter::kFrontal);
  EXPECT_EQ(ab.priority_id, 2u);
  expect_same(ab, pair_conflict(b, a, kGround));
}

TEST(PairConflict, AtACrossingTheEarlierArrivalProceedsAndTiesGoToTheLowerId) {
  // symmetric: same distance to the crossing
  const TrafficAgent a = agent(1, {-1.2, 0, 0}, 0, {{5, 0, 0}});
  const TrafficAgent b = agent(2, {0, -1.2, 0}, kPi / 2, {{0, 5, 0}});
  const PairConflict ab = pair_conflict(a, b, kGround);
  ASSERT_TRUE(ab.found);
  EXPECT_EQ(ab.encounter, Encounter::kCrossing);
  EXPECT_EQ(ab.priority_id, 1u);
  expect_same(ab, pair_conflict(b, a, kGround));
  // robot 2 is 0.5 m closer (1 s at 0.5 m/s, more than the 0.5 s tie): it goes first
  const TrafficAgent b_closer = agent(2, {0, -0.7, 0}, kPi / 2, {{0, 5, 0}});
  EXPECT_EQ(pair_conflict(a, b_closer, kGround).priority_id, 2u);
  // 0.2 m closer is a tie
  const TrafficAgent b_tie = agent(2, {0, -1.0, 0}, kPi / 2, {{0, 5, 0}});
  EXPECT_EQ(pair_conflict(a, b_tie, kGround).priority_id, 1u);
}

TEST(PairConflict, TheRobotAheadProceedsWhenFollowing) {
  const TrafficAgent rear = agent(1, {0, 0, 0}, 0, {{10, 0, 0}});
  const TrafficAgent front = agent(2, {1.5, 0, 0}, 0, {{10, 0, 0}}, 0.2);
  const PairConflict pc = pair_conflict(rear, front, kGround);
  ASSERT_TRUE(pc.found);
  EXPECT_EQ(pc.encounter, Encounter::kFollowing);
  EXPECT_EQ(pc.priority_id, 2u);
}

TEST(PairConflict, AHoldingRobotOnTheWayBlocksAndYields) {
  const TrafficAgent mover = agent(2, {0, 0, 0}, 0, {{10, 0, 0}});
  const TrafficAgent parked = agent(1, {1.2, 0.3, 0}, 0, {}, 0.0);
  const PairConflict pc = pair_conflict(mover, parked, kGround);
  ASSERT_TRUE(pc.found);
  EXPECT_EQ(pc.encounter, Encounter::kBlocking);
  EXPECT_EQ(pc.priority_id, 2u);
}

TEST(PairConflict, ParallelLanesFartherThanTheClearanceDoNotConflict) {
  // clearance: 0.3 + 0.3 + 0.2 m
  const TrafficAgent a = agent(1, {0, 0, 0}, 0, {{10, 0, 0}});
  const TrafficAgent b = agent(2, {2, 0.85, 0}, kPi, {{-8, 0.85, 0}});
  EXPECT_FALSE(pair_conflict(a, b, kGround).found);
  const TrafficAgent c = agent(2, {2, 0.75, 0}, kPi, {{-8, 0.75, 0}});
  EXPECT_TRUE(pair_conflict(a, c, kGround).found);
}

TEST(PairConflict, TheSafetyDistanceGrowsWithSpeed) {
  // the crossing is 2.5 m ahead of both: the paths cut at d(0.5 m/s) = 0.55 + 2 x 0.5 =
  // 1.55 m end 1.34 m apart (more than the 0.8 m clearance); at 1 m/s, d = 2.55 m
  const TrafficAgent a = agent(1, {-2.5, 0, 0}, 0, {{5, 0, 0}});
  const TrafficAgent b = agent(2, {0, -2.5, 0}, kPi / 2, {{0, 5, 0}});
  EXPECT_FALSE(pair_conflict(a, b, kGround).found);
  const TrafficAgent a_fast = agent(1, {-2.5, 0, 0}, 0, {{5, 0, 0}}, 1.0);
  const TrafficAgent b_fast = agent(2, {0, -2.5, 0}, kPi / 2, {{0, 5, 0}}, 1.0);
  EXPECT_TRUE(pair_conflict(a_fast, b_fast, kGround).found);
  EXPECT_DOUBLE_EQ(kGround.safety_distance_m(0.0), 0.55);
  EXPECT_DOUBLE_EQ(kGround.safety_distance_m(0.5), 1.55);
}

TEST(TrafficPolicy, TheCrossingRobotWithoutPriorityStopsAndTheOtherProceeds) {
  const TrafficAgent a = agent(1, {-1.2, 0, 0}, 0, {{5, 0, 0}});
  const TrafficAgent b = agent(2, {0, -1.2, 0}, kPi / 2, {{0, 5, 0}});
  TrafficPolicy pa(kGround), pb(kGround);
  const TrafficDecision da = pa.update(a, std::vector{b}, anywhere(), 0.0);
  const TrafficDecision db = pb.update(b, std::vector{a}, anywhere(), 0.0);
  EXPECT_EQ(da.action, TrafficAction::kProceed);
  EXPECT_EQ(db.action, TrafficAction::kStopAndWait);
  EXPECT_EQ(db.because_of_robot, 1u);
  EXPECT_EQ(db.encounter, Encounter::kCrossing);
  EXPECT_EQ(pb.mode(), TrafficPolicy::Mode::kWaiting);
}

TEST(TrafficPolicy, AFrontalEncounterStepsTheOtherRobotAsideIntoFreeSpace) {
  const TrafficAgent a = agent(1, {0, 0, 0}, 0, {{10, 0, 0}});
  const TrafficAgent b = agent(2, {3, 0, 0}, kPi, {{-7, 0, 0}});
  // free: a 2.4 m wide corridor
  const FreeSpaceQuery corridor = [](const Eigen::Vector3d& p) {
    return std::abs(p.y()) + 0.3 <= 1.2;
  };
  TrafficPolicy pb(kGround);
  const TrafficDecision d = pb.update(b, std::vector{a}, corridor, 0.0);
  ASSERT_EQ(d.action, TrafficAction::kStepAside);
  EXPECT_EQ(d.encounter, Encounter::kFrontal);
  EXPECT_EQ(d.because_of_robot, 1u);
  EXPECT_TRUE(corridor(d.aside_point));
  // beside robot 1's lane by the clearance, on robot 2's right (it faces -x: +y)
  EXPECT_NEAR(d.aside_point.x(), 3.0, 1e-9);
  EXPECT_GE(d.aside_point.y(), 0.8);
  // the same point while the encounter lasts
  const TrafficDecision again = pb.update(b, std::vector{a}, corridor, 0.1);
  EXPECT_EQ(again.action, TrafficAction::kStepAside);
  EXPECT_TRUE(again.aside_point.isApprox(d.aside_point));
}

TEST(TrafficPolicy, WithoutRoomToStepAsideItStopsAndSaysSo) {
  const TrafficAgent a = agent(1, {0, 0, 0}, 0, {{10, 0, 0}});
  const TrafficAgent b = agent(2, {3, 0, 0}, kPi, {{-7, 0, 0}});
  const FreeSpaceQuery narrow = [](const Eigen::Vector3d& p) { return std::abs(p.y()) <= 0.2; };
  TrafficPolicy pb(kGround);
  const TrafficDecision d = pb.update(b, std::vector{a}, narrow, 0.0);
  EXPECT_EQ(d.action, TrafficAction::kStopAndWait);
  EXPECT_TRUE(d.no_aside_point);
  // no free-space query at all: the same
  TrafficPolicy pb2(kGround);
  EXPECT_TRUE(pb2.update(b, std::vector{a}, FreeSpaceQuery{}, 0.0).no_aside_point);
}

TEST(TrafficPolicy, WhenNeitherSideOfThePathHasRoomItStepsAsideAnotherWay) {
  // The parking lot's distributed pair: an idle robot with a wall at its back; the
  // teammate's path turns beside it, toward a goal 0.6 m from its centre. Across the path
  // lies the path itself, behind the robot the wall; east along the wall there is room.
  const TrafficAgent idle = agent(1, {0, 0, 0}, 0, {}, 0.0);
  const TrafficAgent mover = agent(2, {0.3, -1.5, 0}, kPi / 2, {{0.3, -0.6, 0}, {-1.5, -0.6, 0}});
  const FreeSpaceQuery wall_north_box_south = [](const Eigen::Vector3d& p) {
    return p.y() <= 0.0 && p.y() >= -2.0;
  };
  TrafficPolicy p(kGround);
  const TrafficDecision d = p.update(idle, std::vector{mover}, wall_north_box_south, 0.0);
  ASSERT_EQ(d.action, TrafficAction::kStepAside);
  EXPECT_EQ(d.encounter, Encounter::kBlocking);
  EXPECT_FALSE(d.no_aside_point);
  EXPECT_TRUE(wall_north_box_south(d.aside_point));
  // clear of the teammate's whole path by the clearance (0.3 + 0.3 + 0.2 m) and
  // aside_extra_m (0.05)
  Polyline path;
  path.assign(mover.position, mover.path, std::numeric_limits<double>::infinity(), true);
  EXPECT_GE(path.closest(d.aside_point).distance_m, 0.85);
  // the nearest such point on 0.1 m rings from aside_min_move_m (0.2 m): 1 m east along the
  // wall, 0.86 m from the path's corner
  EXPECT_NEAR(d.aside_point.x(), 1.0, 1e-6);
  EXPECT_NEAR(d.aside_point.y(), 0.0, 1e-6);
}

TEST(TrafficPolicy, ABodyInTheCorridorStopsEvenThePriorityRobot) {
  const TrafficAgent a = agent(1, {0, 0, 0}, 0, {{10, 0, 0}});
  // robot 2 stands 1 m ahead, its path going away sideways
  const TrafficAgent b = agent(2, {1.0, 0.1, 0}, kPi / 2, {{1.0, 5, 0}}, 0.0);
  TrafficPolicy pa(kGround);
  const TrafficDecision d = pa.update(a, std::vector{b}, anywhere(), 0.0);
  EXPECT_EQ(d.action, TrafficAction::kStopAndWait);
  EXPECT_EQ(d.because_of_robot, 2u);
  // a robot behind does not stop it
  const TrafficAgent behind = agent(2, {-1.0, 0.1, 0}, kPi / 2, {{-1.0, 5, 0}}, 0.0);
  TrafficPolicy pa2(kGround);
  EXPECT_EQ(pa2.update(a, std::vector{behind}, anywhere(), 0.0).action, TrafficAction::kProceed);
}

TEST(TrafficPolicy, AFollowerOnThePriorityRobotsWayStepsAsideInsteadOfStopping) {
  // two robots side by side, 0.85 m apart, both leaving west (a parking-lot run: r3 and r4
  // held each other 335 s). r4 is a little ahead along r3's heading: following, priority r4;
  // r4's path dips past r3's body, so r4's safety net stops it for r3
  const double deg = kPi / 180;
  const TrafficAgent r3 = agent(3, {0, 0, 0}, 165 * deg, {{-0.9, 0.24, 0}, {-3.3, 0.7, 0}}, 0.0);
  const TrafficAgent r4 =
      agent(4, {0.1, 0.85, 0}, -108 * deg,
            {{-0.05, 0.37, 0}, {-0.4, 0.22, 0}, {-0.9, 0.36, 0}, {-2.3, 0.9, 0}}, 0.0);
  const PairConflict pc = pair_conflict(r3, r4, kGround);
  ASSERT_TRUE(pc.found);
  EXPECT_EQ(pc.encounter, Encounter::kFollowing);
  EXPECT_EQ(pc.priority_id, 4u);

  TrafficPolicy p4(kGround);
  const TrafficDecision d4 = p4.update(r4, std::vector<TrafficAgent>{r3}, anywhere(), 0.0);
  EXPECT_EQ(d4.action, TrafficAction::kStopAndWait);
  EXPECT_EQ(d4.encounter, Encounter::kIntrusion);

  // r3 does not only stop (both would wait): it steps aside, off r4's way
  TrafficPolicy p3(kGround);
  const TrafficDecision d3 = p3.update(r3, std::vector<TrafficAgent>{r4}, anywhere(), 0.0);
  ASSERT_EQ(d3.action, TrafficAction::kStepAside);
  EXPECT_EQ(d3.because_of_robot, 4u);

  // r3 at its aside point, at rest (no path): r4 goes on
  const TrafficAgent r3_aside = agent(3, d3.aside_point, 165 * deg, {}, 0.0);
  EXPECT_EQ(p4.update(r4, std::vector<TrafficAgent>{r3_aside}, anywhere(), 1.0).action,
            TrafficAction::kResume);
}

TEST(TrafficPolicy, ResumesOnceTheTeammateHasCrossedAndLeftTheView) {
  TrafficAgent a = agent(1, {-1.2, 0, 0}, 0, {{5, 0, 0}});
  const TrafficAgent b = agent(2, {0, -1.2, 0}, kPi / 2, {{0, 5, 0}}, 0.0);
  TrafficPolicy pb(kGround);
  ASSERT_EQ(pb.update(b, std::vector{a}, anywhere(), 0.0).action, TrafficAction::kStopAndWait);
  // robot 1 is past the crossing but still in robot 2's view, 1 m away: keep waiting
  a.position = {0.6, 0, 0};
  EXPECT_EQ(pb.update(b, std::vector{a}, anywhere(), 1.0).action, TrafficAction::kStopAndWait);
  // out of view (more than 45 degrees off the heading) and out of the corridor
  a.position = {2.0, 0, 0};
  const TrafficDecision r = pb.update(b, std::vector{a}, anywhere(), 2.0);
  EXPECT_EQ(r.action, TrafficAction::kResume);
  EXPECT_EQ(r.because_of_robot, 1u);
  EXPECT_DOUBLE_EQ(r.held_s, 2.0);
  EXPECT_EQ(pb.update(b, std::vector{a}, anywhere(), 2.1).action, TrafficAction::kProceed);
}

TEST(TrafficPolicy, AHoldLongerThanMaxWaitAsksOnceForReplanning) {
  TrafficConfig c = kGround;
  c.max_wait_s = 5;
  const TrafficAgent a = agent(1, {-1.2, 0, 0}, 0, {{5, 0, 0}}, 0.0);
  const TrafficAgent b = agent(2, {0, -1.2, 0}, kPi / 2, {{0, 5, 0}}, 0.0);
  TrafficPolicy pb(c);
  int requests = 0;
  for (int i = 0; i <= 200; ++i) {
    const TrafficDecision d = pb.update(b, std::vector{a}, anywhere(), 0.1 * i);
    EXPECT_EQ(d.action, TrafficAction::kStopAndWait);
    if (d.request_replan) {
      ++requests;
      EXPECT_GT(d.held_s, 5.0);
      EXPECT_LT(d.held_s, 5.2);
    }
  }
  EXPECT_EQ(requests, 1);
  // a new plan: the hold starts over
  pb.reset();
  EXPECT_EQ(pb.mode(), TrafficPolicy::Mode::kFree);
}

TEST(TrafficPolicy, IgnoresItselfAndNonFiniteTeammatesAndHoldsOnANonFiniteOwnState) {
  const TrafficAgent a = agent(1, {0, 0, 0}, 0, {{10, 0, 0}});
  TrafficAgent bad = agent(2, {2, 0, 0}, kPi, {{-8, 0, 0}});
  bad.position.x() = std::nan("");
  TrafficPolicy p(kGround);
  EXPECT_EQ(p.update(a, std::vector{a, bad}, anywhere(), 0.0).action, TrafficAction::kProceed);
  TrafficAgent lost = a;
  lost.yaw_rad = std::nan("");
  EXPECT_EQ(p.update(lost, std::vector<TrafficAgent>{}, anywhere(), 0.1).action,
            TrafficAction::kStopAndWait);
}

TEST(TrafficConfig, ThesisDefaultsPerKindAreValid) {
  EXPECT_TRUE(kGround.validate().empty());
  const TrafficConfig aerial = TrafficConfig::for_kind(RobotKind::kMultirotor);
  EXPECT_TRUE(aerial.validate().empty());
  EXPECT_DOUBLE_EQ(aerial.d0_m, 1.0);
  EXPECT_DOUBLE_EQ(kGround.d0_m, 0.55);
  TrafficConfig bad = kGround;
  bad.frontal_angle_deg = 95;
  bad.sample_step_m = 0;
  EXPECT_NE(bad.validate().find("sample_step_m"), std::string::npos);
  EXPECT_NE(bad.validate().find("frontal_angle_deg"), std::string::npos);
}

}  // namespace
}  // namespace scancrew::motion
