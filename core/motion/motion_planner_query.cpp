// MotionPlanner::Impl's query: the request checked, LazyPRM* on the roadmap, the path
// shortcut and checked again, or the status that says why not.

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include "core/motion/motion_planner_impl.hpp"

namespace scancrew::motion {

std::optional<PlanResult> MotionPlanner::Impl::check_request(const PlanRequest& q) {
  char buf[256];
  if (!finite(q.start) || !finite(q.goal))
    return fail(PlanStatus::kBadInput, "start or goal pose is not finite", q.goal);
  if (!ground() && (q.goal.position.z < config.multirotor_min_altitude_m ||
                    q.goal.position.z > config.multirotor_max_altitude_m)) {
    std::snprintf(buf, sizeof buf, "goal altitude %.2f m outside [%.2f, %.2f] m", q.goal.position.z,
                  config.multirotor_min_altitude_m, config.multirotor_max_altitude_m);
    return fail(PlanStatus::kBadInput, buf, q.goal);
  }
  if (!map.has_map()) return fail(PlanStatus::kMapStale, "no map yet", q.goal);
  const double age_s = 1e-9 * static_cast<double>(q.pose_stamp_ns - map_stamp_ns);
  if (age_s > config.max_map_age_s) {
    std::snprintf(buf, sizeof buf, "map is %.2f s older than the pose (max %.2f s)", age_s,
                  config.max_map_age_s);
    return fail(PlanStatus::kMapStale, buf, q.goal);
  }
  if (map.collides(pose_of(q.start))) {
    std::snprintf(buf, sizeof buf, "body at the start (%.2f, %.2f, %.2f) overlaps %s",
                  q.start.position.x, q.start.position.y, q.start.position.z,
                  config.unknown_is_occupied ? "occupied or unknown space" : "occupied space");
    return fail(PlanStatus::kStartInCollision, buf, q.goal);
  }
  if (config.unknown_is_occupied && map.state_at(center_of(q.goal)) == tsdf::VoxelState::kUnknown) {
    std::snprintf(buf, sizeof buf, "goal (%.2f, %.2f, %.2f) is in unknown space", q.goal.position.x,
                  q.goal.position.y, q.goal.position.z);
    return fail(PlanStatus::kGoalUnknown, buf, q.goal);
  }
  if (map.collides(pose_of(q.goal))) {
    std::snprintf(buf, sizeof buf, "body at the goal (%.2f, %.2f, %.2f) overlaps %s",
                  q.goal.position.x, q.goal.position.y, q.goal.position.z,
                  config.unknown_is_occupied ? "occupied or unknown space" : "occupied space");
    return fail(PlanStatus::kGoalInCollision, buf, q.goal);
  }
  return std::nullopt;
}

// searches the roadmap from start to goal and shortcuts the path found into `path`; the
// failure when no path was found
std::optional<PlanResult> MotionPlanner::Impl::search(const PlanRequest& q,
                                                      const ob::ScopedState<>& start,
                                                      const ob::ScopedState<>& goal,
                                                      double straight, og::PathGeometric& path,
                                                      PlanStats& stats, size_t checks0,
                                                      Clock::time_point t0) {
  if (planner->vertex_count() > static_cast<size_t>(config.roadmap_max_vertices)) {
    planner->clear();
    stats.roadmap_cleared = true;
  }
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  pdef->setStartAndGoalStates(start, goal, config.goal_tolerance_m);
  objective->setCostThreshold(config.path_cost_factor > 0
                                  ? ob::Cost(config.path_cost_factor * straight)
                                  : objective->infiniteCost());
  pdef->setOptimizationObjective(objective);
  planner->setProblemDefinition(pdef);  // clearQuery(): the roadmap stays
  // with unknown space free the grid is mostly free and guides little; in the parking-lot
  // mission (unknown free) it was seen to leave a robot stuck on its path: not used there
  if (ground() && config.guide_grid && config.unknown_is_occupied) {
    if (!planner->isSetup()) planner->setup();
    add_guide(q.start, q.goal, stats);
  }
  const auto ts = Clock::now();
  ob::PlannerStatus status = ob::PlannerStatus::UNKNOWN;
  std::string error;
  try {
    status = planner->solve(ob::timedPlannerTerminationCondition(config.planner_time_limit_s));
  } catch (const std::exception& e) {
    error = e.what();
  }
  stats.solve_ms = ms_since(ts);
  stats.searches = planner->last_solve().searches;
  stats.search_cut = planner->last_solve().cut_in_repair;
  stats.roadmap_vertices = planner->vertex_count();
  stats.roadmap_edges = planner->edge_count();
  if (status != ob::PlannerStatus::EXACT_SOLUTION || !pdef->hasSolution())
    return search_failed(q, status, error, stats, checks0, t0);
  path = *pdef->getSolutionPath()->as<og::PathGeometric>();
  stats.raw_length_m = path.length();
  // shortcutting (vertex reduction, then random shortcuts), kept only if still valid
  const auto tsimp = Clock::now();
  og::PathGeometric raw = path;
  og::PathSimplifier simplifier(si);
  simplifier.reduceVertices(path);
  simplifier.shortcutPath(path);
  if (!path.check()) path = raw;
  stats.simplify_ms = ms_since(tsimp);
  return std::nullopt;
}

// the result of a search that found no path: a timeout or a planner error, with its stats
PlanResult MotionPlanner::Impl::search_failed(const PlanRequest& q, const ob::PlannerStatus& status,
                                              const std::string& error, const PlanStats& stats,
                                              size_t checks0, Clock::time_point t0) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "no path from (%.2f, %.2f, %.2f) to (%.2f, %.2f, %.2f) in %.0f ms (%s%s%s)",
                q.start.position.x, q.start.position.y, q.start.position.z, q.goal.position.x,
                q.goal.position.y, q.goal.position.z, stats.solve_ms, status.asString().c_str(),
                error.empty() ? "" : ": ", error.c_str());
  // OMPL's TIMEOUT (ours when the roadmap holds no path), APPROXIMATE or no solution
  // path: out of time; anything else: OMPL refused the query or threw
  const bool timeout = error.empty() && (status == ob::PlannerStatus::TIMEOUT ||
                                         status == ob::PlannerStatus::APPROXIMATE_SOLUTION ||
                                         status == ob::PlannerStatus::EXACT_SOLUTION);
  PlanResult f = fail(timeout ? PlanStatus::kTimeout : PlanStatus::kPlannerError, buf, q.goal);
  f.stats = stats;
  f.stats.collision_checks = map.checks() - checks0;
  f.stats.total_ms = ms_since(t0);
  return f;
}

PlanResult MotionPlanner::Impl::plan(const PlanRequest& q) {
  const auto t0 = Clock::now();
  const size_t checks0 = map.checks();

  if (std::optional<PlanResult> rejected = check_request(q)) return std::move(*rejected);

  Eigen::AlignedBox3d ends(center_of(q.start));
  ends.extend(center_of(q.goal));
  grow_bounds(ends);

  PlanResult r;
  ob::ScopedState<> start(space), goal(space);
  set_state(start.get(), q.start);
  set_state(goal.get(), q.goal);
  const double straight = si->distance(start.get(), goal.get());
  const double ground_z = q.start.position.z;

  og::PathGeometric path(si);
  if (straight <= config.goal_tolerance_m || si->checkMotion(start.get(), goal.get())) {
    path.append(start.get());
    path.append(goal.get());
    r.stats.direct = true;
    r.stats.raw_length_m = straight;
  } else if (std::optional<PlanResult> failed =
                 search(q, start, goal, straight, path, r.stats, checks0, t0)) {
    return std::move(*failed);
  }
  r.stats.roadmap_vertices = planner->vertex_count();
  r.stats.roadmap_edges = planner->edge_count();
  r.stats.length_m = path.length();
  r.path.reserve(path.getStateCount());
  for (size_t i = 0; i < path.getStateCount(); ++i)
    r.path.push_back(waypoint_of(path.getState(i), ground_z));
  // the caller's exact poses at both ends (OMPL's yaw is normalised)
  r.path.front() = q.start;
  r.path.back().yaw_rad = q.goal.yaw_rad;
  r.path.back().position = {q.goal.position.x, q.goal.position.y,
                            ground() ? ground_z : q.goal.position.z};
  r.status = PlanStatus::kOk;
  r.stats.collision_checks = map.checks() - checks0;
  r.stats.total_ms = ms_since(t0);
  last_logged.reset();
  return r;
}

}  // namespace scancrew::motion
