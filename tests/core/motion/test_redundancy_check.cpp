// RedundancyCheck (thesis 4.5.2 item 6, Algorithm 6 lines 5-8, Fig. 4.4). In the figure,
// robot 1 (blue) and robot 2 (red) follow their tours of clusters (green disks); one cluster
// (red disk) is in both tours. Situation 1: the robot with fewer steps to it keeps it, the
// other follows its tour up to the cluster before it and waits for a new plan. Situation 2:
// both reach it in the same number of steps: the closer one keeps it.

#include <gtest/gtest.h>

#include <vector>

#include "core/motion/redundancy_check.hpp"

namespace scancrew::motion {
namespace {

TourProgress robot(uint32_t id, Eigen::Vector3d at, std::vector<TourStop> tour, size_t next = 0) {
  TourProgress p;
  p.robot_id = id;
  p.position = at;
  p.tour = std::move(tour);
  p.next = next;
  return p;
}

const RedundancyConfig kConfig;
// the doubly assigned cluster; the robots' maps gave it different ids (distributed maps)
const Eigen::Vector3d kRed(5, 5, 0);

TEST(RedundancyCheck, WithoutADoublyAssignedClusterNothingHappens) {
  const TourProgress r1 = robot(1, {0, 0, 0}, {{10, {2, 0, 0}}, {11, {4, 0, 0}}});
  const TourProgress r2 = robot(2, {0, 8, 0}, {{20, {2, 8, 0}}, {21, {4, 8, 0}}});
  const RedundancyResult a = redundancy_check(r1, std::vector{r2}, kConfig);
  EXPECT_FALSE(a.redundancy);
  EXPECT_TRUE(a.contests.empty());
  EXPECT_FALSE(a.stop_before_index);
}

TEST(RedundancyCheck, Situation1TheRobotWithFewerStepsKeepsTheCluster) {
  // robot 1: two steps to the red cluster, 7.07 m along its tour; robot 2: three steps but
  // only 5.54 m (the steps decide, not the distance)
  const TourProgress r1 = robot(1, {0, 0, 0}, {{10, {4, 4, 0}}, {11, kRed}, {12, {8, 8, 0}}});
  const TourProgress r2 = robot(
      2, {5, 10, 0}, {{20, {5, 9, 0}}, {21, {6, 8, 0}}, {22, kRed + Eigen::Vector3d(0.1, 0, 0)}});
  const RedundancyResult a = redundancy_check(r1, std::vector{r2}, kConfig);
  const RedundancyResult b = redundancy_check(r2, std::vector{r1}, kConfig);
  ASSERT_EQ(a.contests.size(), 1u);
  ASSERT_EQ(b.contests.size(), 1u);
  EXPECT_TRUE(a.contests[0].won);
  EXPECT_EQ(a.contests[0].steps, 2u);
  EXPECT_FALSE(b.contests[0].won);
  EXPECT_EQ(b.contests[0].winner_id, 1u);
  EXPECT_EQ(b.contests[0].steps, 3u);
  EXPECT_EQ(b.contests[0].winner_steps, 2u);
  EXPECT_LT(b.contests[0].distance_m, a.contests[0].distance_m);
  // the priority robot goes on; the other keeps going for now...
  EXPECT_FALSE(a.redundancy);
  EXPECT_FALSE(b.redundancy);
  ASSERT_TRUE(b.stop_before_index);
  EXPECT_EQ(*b.stop_before_index, 2u);
  // ...up to the cluster before the red one, and there waits for a new plan
  TourProgress r2_later = r2;
  r2_later.position = {6, 8, 0};
  r2_later.next = 2;
  TourProgress r1_later = r1;
  r1_later.position = {4, 4, 0};
  r1_later.next = 1;
  EXPECT_TRUE(redundancy_check(r2_later, std::vector{r1_later}, kConfig).redundancy);
  EXPECT_FALSE(redundancy_check(r1_later, std::vector{r2_later}, kConfig).redundancy);
}

TEST(RedundancyCheck, Situation2OnEqualStepsTheCloserRobotKeepsTheCluster) {
  // both have the red cluster next; robot 2 is 3 m from it, robot 1 4 m
  const TourProgress r1 = robot(1, {1, 5, 0}, {{10, kRed}, {11, {9, 9, 0}}});
  const TourProgress r2 = robot(2, {5, 8, 0}, {{20, kRed}, {21, {9, 1, 0}}});
  const RedundancyResult a = redundancy_check(r1, std::vector{r2}, kConfig);
  const RedundancyResult b = redundancy_check(r2, std::vector{r1}, kConfig);
  ASSERT_EQ(a.contests.size(), 1u);
  EXPECT_FALSE(a.contests[0].won);
  EXPECT_EQ(a.contests[0].winner_id, 2u);
  EXPECT_DOUBLE_EQ(a.contests[0].distance_m, 4.0);
  EXPECT_DOUBLE_EQ(a.contests[0].winner_distance_m, 3.0);
  EXPECT_TRUE(a.redundancy) << "robot 1 waits for a new plan";
  EXPECT_FALSE(b.redundancy) << "robot 2 continues";
  EXPECT_TRUE(b.contests[0].won);
}

TEST(RedundancyCheck, Situation2WithThreeRobotsArrivingTogether) {
  const TourProgress r1 = robot(1, {1, 5, 0}, {{10, kRed}});
  const TourProgress r2 = robot(2, {5, 8, 0}, {{20, kRed}});
  const TourProgress r3 = robot(3, {6, 5, 0}, {{30, kRed}});  // 1 m: the closest
  const std::vector team = {r1, r2, r3};
  size_t keepers = 0;
  for (const TourProgress& self : team) {
    const RedundancyResult r = redundancy_check(self, team, kConfig);
    ASSERT_EQ(r.contests.size(), 1u);
    EXPECT_EQ(r.contests[0].winner_id, 3u);
    EXPECT_EQ(r.redundancy, self.robot_id != 3);
    keepers += r.contests[0].won ? 1 : 0;
  }
  EXPECT_EQ(keepers, 1u) << "exactly one robot keeps the cluster";
}

TEST(RedundancyCheck, ExactTiesGoToTheLowerId) {
  const TourProgress r1 = robot(1, {0, 5, 0}, {{10, kRed}});
  const TourProgress r2 = robot(2, {10, 5, 0}, {{20, kRed}});
  EXPECT_FALSE(redundancy_check(r1, std::vector{r2}, kConfig).redundancy);
  EXPECT_TRUE(redundancy_check(r2, std::vector{r1}, kConfig).redundancy);
}

TEST(RedundancyCheck, AClusterATeammateHasAlreadyReachedIsTaken) {
  // robot 2 has passed the red cluster (next = 1): zero steps
  const TourProgress r1 = robot(1, {5, 4, 0}, {{10, kRed}});
  const TourProgress r2 = robot(2, {9, 9, 0}, {{20, kRed}, {21, {9, 9, 0}}}, 1);
  const RedundancyResult a = redundancy_check(r1, std::vector{r2}, kConfig);
  EXPECT_TRUE(a.redundancy);
  EXPECT_EQ(a.contests[0].winner_steps, 0u);
}

TEST(RedundancyCheck, AnotherRobotTakesOverWhenThePriorityRobotsNewPlanDropsTheCluster) {
  const TourProgress r1 = robot(1, {1, 5, 0}, {{10, kRed}});
  TourProgress r2 = robot(2, {5, 8, 0}, {{20, kRed}});
  ASSERT_TRUE(redundancy_check(r1, std::vector{r2}, kConfig).redundancy);
  r2.tour = {{25, {9, 9, 0}}};  // robot 2 re-planned without it
  EXPECT_FALSE(redundancy_check(r1, std::vector{r2}, kConfig).redundancy);
}

TEST(RedundancyCheck, ClustersMatchByGoalOrOptionallyById) {
  const TourProgress r1 = robot(1, {1, 5, 0}, {{7, kRed}});
  const TourProgress r2_far = robot(2, {5, 8, 0}, {{7, {5, 6, 0}}});  // same id, 1 m off
  EXPECT_TRUE(redundancy_check(r1, std::vector{r2_far}, kConfig).contests.empty());
  RedundancyConfig by_id = kConfig;
  by_id.match_cluster_ids = true;
  EXPECT_EQ(redundancy_check(r1, std::vector{r2_far}, by_id).contests.size(), 1u);
  // ground robots compare goals in the plane
  const TourProgress r2_high = robot(2, {5, 8, 0}, {{20, kRed + Eigen::Vector3d(0, 0, 2)}});
  EXPECT_TRUE(redundancy_check(r1, std::vector{r2_high}, kConfig).contests.empty());
  RedundancyConfig planar = kConfig;
  planar.planar = true;
  EXPECT_EQ(redundancy_check(r1, std::vector{r2_high}, planar).contests.size(), 1u);
}

TEST(RedundancyCheck, ADoneOrBrokenTourIsHarmless) {
  const TourProgress done = robot(1, {0, 0, 0}, {{10, kRed}}, 1);
  const TourProgress r2 = robot(2, {5, 8, 0}, {{20, kRed}});
  EXPECT_FALSE(redundancy_check(done, std::vector{r2}, kConfig).redundancy);
  TourProgress broken = r2;
  broken.position.x() = std::nan("");
  EXPECT_TRUE(redundancy_check(robot(1, {1, 5, 0}, {{10, kRed}}), std::vector{broken}, kConfig)
                  .contests.empty());
}

}  // namespace
}  // namespace scancrew::motion
