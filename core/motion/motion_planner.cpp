#include "core/motion/motion_planner.hpp"

#include <chrono>
#include <memory>
#include <utility>

#include "core/motion/motion_planner_impl.hpp"

namespace scancrew::motion {

std::string_view to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::kOk:
      return "ok";
    case PlanStatus::kTimeout:
      return "timeout";
    case PlanStatus::kPlannerError:
      return "planner_error";
    case PlanStatus::kStartInCollision:
      return "start_in_collision";
    case PlanStatus::kGoalInCollision:
      return "goal_in_collision";
    case PlanStatus::kGoalUnknown:
      return "goal_unknown";
    case PlanStatus::kMapStale:
      return "map_stale";
    case PlanStatus::kBadInput:
      return "bad_input";
  }
  return "?";
}

RoadmapDistances MotionPlanner::Impl::roadmap_distances(const msg::Waypoint& from,
                                                        const std::vector<msg::Waypoint>& targets) {
  const auto t0 = Clock::now();
  const size_t checks0 = map.checks();
  RoadmapDistances r;
  char buf[160];
  if (!finite(from)) {
    r.message = "the pose to measure from is not finite";
    return r;
  }
  if (!map.has_map()) {
    r.status = PlanStatus::kMapStale;
    r.message = "no map yet";
    return r;
  }
  if (map.collides(pose_of(from))) {
    r.status = PlanStatus::kStartInCollision;
    std::snprintf(buf, sizeof buf, "body at (%.2f, %.2f, %.2f) overlaps %s", from.position.x,
                  from.position.y, from.position.z,
                  config.unknown_is_occupied ? "occupied or unknown space" : "occupied space");
    r.message = buf;
    return r;
  }
  // the targets that plan() would accept as goals; the rest stay +inf
  std::vector<bool> valid(targets.size(), false);
  Eigen::AlignedBox3d ends(center_of(from));
  for (size_t t = 0; t < targets.size(); ++t) {
    valid[t] = valid_goal(targets[t]);
    if (valid[t]) ends.extend(center_of(targets[t]));
  }
  grow_bounds(ends);
  ob::ScopedState<> start(space);
  set_state(start.get(), from);
  std::vector<ob::ScopedState<>> goals;
  goals.reserve(targets.size());
  std::vector<const ob::State*> goal_states(targets.size(), nullptr);
  for (size_t t = 0; t < targets.size(); ++t) {
    if (!valid[t]) continue;
    goals.emplace_back(space);
    set_state(goals.back().get(), targets[t]);
    goal_states[t] = goals.back().get();
  }

  ensure_setup(start.get());
  planner->clearQuery();  // the last plan()'s start and goal vertices may be deleted below
  if (planner->vertex_count() > static_cast<size_t>(config.roadmap_max_vertices)) planner->clear();
  const auto t_grow = Clock::now();
  r.grown_vertices =
      planner->grow(static_cast<size_t>(std::min(config.roadmap_distance_min_vertices,
                                                 config.roadmap_max_vertices)),
                    ob::timedPlannerTerminationCondition(config.roadmap_distance_grow_time_s));
  r.grow_ms = ms_since(t_grow);
  auto found = planner->distances(start.get(), goal_states, [this](const ob::State* s) {
    return Eigen::Vector3d(pose_of(s).translation());
  });
  r.status = PlanStatus::kOk;
  r.distances_m = std::move(found.distances_m);
  r.checked_edges = found.checked_edges;
  r.removed_edges = found.removed_edges;
  r.removed_vertices = found.removed_vertices;
  r.roadmap_vertices = planner->vertex_count();
  r.collision_checks = map.checks() - checks0;
  r.ms = ms_since(t0);
  return r;
}

// the failure of a request whose poses are bad, whose map is missing or stale, or whose
// start or goal is in collision; nothing when it can be planned
Result<MotionPlanner, std::string> MotionPlanner::create(const PlannerConfig& config) {
  if (const std::string e = config.validate(); !e.empty()) return make_unexpected(e);
  configure_ompl_once(config.seed);
  return MotionPlanner(std::make_unique<Impl>(config));
}

MotionPlanner::MotionPlanner(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MotionPlanner::~MotionPlanner() = default;
MotionPlanner::MotionPlanner(MotionPlanner&&) noexcept = default;
MotionPlanner& MotionPlanner::operator=(MotionPlanner&&) noexcept = default;

MapUpdateStats MotionPlanner::update_map(std::shared_ptr<const tsdf::MapSnapshot> map,
                                         int64_t stamp_ns) {
  const auto t0 = Clock::now();
  Impl& m = *impl_;
  MapUpdateStats s;
  if (!map) return s;
  const CollisionMapUpdate u = m.map.update(std::move(map));
  m.map_stamp_ns = stamp_ns;
  s.changed_blocks = u.changed.size();
  s.rebuilt = u.rebuilt;
  if (u.rebuilt) {
    s.forgotten_vertices = m.planner->vertex_count();
    s.forgotten_edges = m.planner->edge_count();
    m.planner->clearValidity();
  } else {
    std::tie(s.forgotten_vertices, s.forgotten_edges) = m.forget_near(u.changed);
  }
  m.grow_bounds(m.map.extents());
  s.ms = ms_since(t0);
  return s;
}

PlanResult MotionPlanner::plan(const PlanRequest& request) {
  return impl_->plan(request);
}

RoadmapDistances MotionPlanner::roadmap_distances(const msg::Waypoint& from,
                                                  const std::vector<msg::Waypoint>& targets) {
  return impl_->roadmap_distances(from, targets);
}

bool MotionPlanner::is_free(const msg::Waypoint& pose) const {
  const Impl& m = *impl_;
  return m.map.has_map() && finite(pose) && !m.map.collides(m.pose_of(pose)) &&
         m.clear_of_parked(m.center_of(pose));
}
void MotionPlanner::set_parked(std::vector<Eigen::Vector3d> centers, double radius_m) {
  Impl& m = *impl_;
  if (centers == m.parked && radius_m == m.parked_radius_m) return;
  m.parked_radius_m = radius_m;
  const double reach = m.body.bounding_radius_m() + radius_m;
  for (const Eigen::Vector3d& c : centers)
    if (std::find(m.parked.begin(), m.parked.end(), c) == m.parked.end()) m.forget_ball(c, reach);
  m.parked = std::move(centers);
}
void MotionPlanner::clear_roadmap() {
  impl_->planner->clear();
}
size_t MotionPlanner::roadmap_vertices() const {
  return impl_->planner->vertex_count();
}
const PlannerConfig& MotionPlanner::config() const {
  return impl_->config;
}
const robot::BodyModel& MotionPlanner::body() const {
  return impl_->body;
}

}  // namespace scancrew::motion
