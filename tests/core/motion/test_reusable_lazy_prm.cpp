// ReusableLazyPrmStar::solve (core/motion/reusable_lazy_prm.hpp) on a 10 × 10 m plane
// with a wall between start and goal and a hand-placed roadmap: the shortest path on the lazy
// roadmap crosses the wall, so the first search finds a path that the checks reject, and
// the planner has to repair it (delete the invalid edges, search again) to get around.
// The termination condition stops that repair (LazyPRM's own solve() goes on searching
// until the path is valid or start and goal are cut apart); a later query on the same
// roadmap still finds a valid path around.

#include <gtest/gtest.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <limits>
#include <memory>
#include <mutex>

#include "core/motion/reusable_lazy_prm.hpp"

namespace scancrew::motion {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

// the wall: x in [4.5, 5.5], y in [0, 8]; the way around is through y > 8
bool in_wall(double x, double y) {
  return x >= 4.5 && x <= 5.5 && y <= 8.0;
}

struct Plane {
  std::shared_ptr<ob::RealVectorStateSpace> space = std::make_shared<ob::RealVectorStateSpace>(2);
  ob::SpaceInformationPtr si;
  std::shared_ptr<ReusableLazyPrmStar> planner;

  Plane() {
    static std::once_flag once;
    std::call_once(once, [] {
      ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
      ompl::RNG::setSeed(1);  // solve() adds its own samples too
    });
    space->setBounds(0.0, 10.0);
    si = std::make_shared<ob::SpaceInformation>(space);
    si->setStateValidityChecker([](const ob::State* s) {
      const double* v = s->as<ob::RealVectorStateSpace::StateType>()->values;
      return !in_wall(v[0], v[1]);
    });
    si->setStateValidityCheckingResolution(0.005);  // 7 cm on the 14 m diagonal
    si->setup();
    planner = std::make_shared<ReusableLazyPrmStar>(si);
  }

  // cost_threshold_m: a path this short or shorter ends the search; +inf (the low-level
  // planner's path_cost_factor 0): the first path found
  ob::ProblemDefinitionPtr query(
      double x0, double y0, double x1, double y1,
      double cost_threshold_m = std::numeric_limits<double>::infinity()) {
    ob::ScopedState<> start(space), goal(space);
    start[0] = x0;
    start[1] = y0;
    goal[0] = x1;
    goal[1] = y1;
    auto pdef = std::make_shared<ob::ProblemDefinition>(si);
    pdef->setStartAndGoalStates(start, goal);
    auto objective = std::make_shared<ob::PathLengthOptimizationObjective>(si);
    objective->setCostThreshold(ob::Cost(cost_threshold_m));
    pdef->setOptimizationObjective(objective);
    planner->setProblemDefinition(pdef);
    return pdef;
  }

  // milestones every metre off the wall: the roadmap's straight line from (2, 4) to (8, 4)
  // is 6 m; around the wall it is over 10 m
  void grid_roadmap() {
    if (!planner->isSetup()) planner->setup();
    ob::ScopedState<> s(space);
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j) {
        s[0] = 0.5 + i;
        s[1] = 0.5 + j;
        if (!in_wall(s[0], s[1])) planner->add_checked_milestone(s.get());
      }
  }
};

TEST(ReusableLazyPrmStar, TheTimeLimitStopsTheRepairOfAPathThatCrossesTheWall) {
  Plane plane;
  plane.query(2, 4, 8, 4);
  plane.grid_roadmap();
  // fires as soon as one search has run: the repair loop must look at it
  const ReusableLazyPrmStar& p = *plane.planner;
  const ob::PlannerTerminationCondition after_one_search(
      [&p] { return p.last_solve().searches >= 1; });
  const ob::PlannerStatus status = plane.planner->solve(after_one_search);
  EXPECT_EQ(status, ob::PlannerStatus::TIMEOUT);
  EXPECT_EQ(p.last_solve().searches, 1u);
  EXPECT_TRUE(p.last_solve().cut_in_repair);
}

TEST(ReusableLazyPrmStar, WithTimeLeftTheRepairGoesAroundTheWallAndTheRoadmapStaysUsable) {
  Plane plane;
  plane.query(2, 4, 8, 4);
  plane.grid_roadmap();
  const ReusableLazyPrmStar& p = *plane.planner;
  // a cut query first, then one with time: the repair picks up where the cut one stopped
  ASSERT_EQ(plane.planner->solve(
                ob::PlannerTerminationCondition([&p] { return p.last_solve().searches >= 1; })),
            ob::PlannerStatus::TIMEOUT);

  const ob::ProblemDefinitionPtr pdef = plane.query(2, 4, 8, 4);
  // bounded by searches, not by time: the repair takes over a hundred on this roadmap
  const ob::PlannerStatus status = plane.planner->solve(
      ob::PlannerTerminationCondition([&p] { return p.last_solve().searches >= 100000; }));
  ASSERT_EQ(status, ob::PlannerStatus::EXACT_SOLUTION);
  EXPECT_GT(p.last_solve().searches, 10u);  // 143 with seed 1: one edge deleted a search
  EXPECT_FALSE(p.last_solve().cut_in_repair);
  const auto& path = *pdef->getSolutionPath()->as<og::PathGeometric>();
  EXPECT_TRUE(path.check());
  EXPECT_GT(path.length(), 10.0);  // around the wall
}

TEST(ReusableLazyPrmStar, AClearLineIsFoundInOneSearch) {
  Plane plane;
  const ob::ProblemDefinitionPtr pdef = plane.query(1, 9.5, 9, 9.5);
  plane.grid_roadmap();
  const ReusableLazyPrmStar& p = *plane.planner;
  const ob::PlannerStatus status = plane.planner->solve(
      ob::PlannerTerminationCondition([&p] { return p.last_solve().searches >= 100000; }));
  ASSERT_EQ(status, ob::PlannerStatus::EXACT_SOLUTION);
  EXPECT_EQ(p.last_solve().searches, 1u);
  EXPECT_FALSE(p.last_solve().cut_in_repair);
  EXPECT_TRUE(pdef->getSolutionPath()->as<og::PathGeometric>()->check());
}

TEST(ReusableLazyPrmStar, WhileOptimizingTheConditionEndsTheSolveWithTheBestPathSoFar) {
  Plane plane;
  // 8 m apart: a 1 m threshold is never met, so the solve keeps growing the roadmap and
  // searching again (each time 5 milestones have joined the path's component) until the
  // condition fires
  const ob::ProblemDefinitionPtr pdef = plane.query(1, 9.5, 9, 9.5, 1.0);
  plane.grid_roadmap();
  const ReusableLazyPrmStar& p = *plane.planner;
  const ob::PlannerStatus status = plane.planner->solve(
      ob::PlannerTerminationCondition([&p] { return p.last_solve().searches >= 3; }));
  ASSERT_EQ(status, ob::PlannerStatus::EXACT_SOLUTION);
  EXPECT_GE(p.last_solve().searches, 3U);
  EXPECT_FALSE(pdef->hasOptimizedSolution());
  const auto& path = *pdef->getSolutionPath()->as<og::PathGeometric>();
  EXPECT_TRUE(path.check());
  EXPECT_GE(path.length(), 8.0 - 1e-9);
}

}  // namespace
}  // namespace scancrew::motion
