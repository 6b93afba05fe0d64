#pragma once

// MotionPlanner: the core of the low-level planner (thesis 2.5.3, Algorithm 1's LazyPRM*
// call; 3.5.2, 4.5.2): a collision-free path from the robot's pose to a goal pose in the
// free space of the latest map snapshot.
//
//   - LazyPRM* (Hauser 2015) from OMPL (Şucan et al. 2012) on SE(2) for ground robots (the
//     body at a fixed height) and on R³ × SO(2) (x, y, z, yaw) for multirotors, sampling
//     inside the observed blocks' box plus a margin (grown to hold start and goal; a
//     multirotor's z within its altitude limits);
//   - state validity: the body (robot_body.hpp) against the CollisionMap's FCL octree
//     (occupied space, unknown too by config), updated incrementally from the snapshots;
//   - the roadmap is kept across queries (a query only adds its start and goal); when the
//     map changes, the validity LazyPRM cached for vertices and edges whose body might
//     reach a changed block is forgotten, so they are checked again on their next use
//     (LazyPRM trusts a vertex or edge it once found valid for ever, and deletes the
//     invalid ones); the roadmap is dropped when it grows past roadmap_max_vertices;
//   - the path is shortcut (OMPL's PathSimplifier: vertex reduction, then shortcutting)
//     and checked again before it is returned;
//   - roadmap_distances(): one-to-many travel distances over the same roadmap (the
//     high-level planner's d(τ_kl), thesis eq. 2.3): one Dijkstra from `from`, the
//     straight motions from `from` and into each target and the links to their nearest
//     roadmap vertices checked lazily (an edge only when it would settle a vertex or a
//     target; roadmap edges' and vertices' validity cached or, when invalid, deleted as
//     LazyPRM does); a sparse roadmap is grown first (roadmap_distance_min_vertices,
//     roadmap_distance_grow_time_s).
//
// Bad input gives a status, never an exception or a loop without end: NaN/inf poses
// (kBadInput), no map or a map older than the pose by more than max_map_age_s
// (kMapStale), a start whose body collides (kStartInCollision), a goal in unknown space
// with unknown_is_occupied (kGoalUnknown) or whose body collides (kGoalInCollision), no
// path within planner_time_limit_s (kTimeout), OMPL refusing the query (kPlannerError). A failing
// status is logged once per (status, goal); the caller decides (replan, wait, back off).
//
// Thread safety: none; one thread maps and plans. OMPL, FCL and OctoMap stay in the .cpp
// files (the private motion_planner_impl.hpp).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/motion/planner_config.hpp"
#include "core/result.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::motion {

enum class PlanStatus : uint8_t {
  kOk,
  // None found within planner_time_limit_s. LazyPRM* is probabilistically complete: it
  // never proves that no path exists (OMPL's INFEASIBLE), so no path is a timeout.
  kTimeout,
  // OMPL refused the query or failed (its own INVALID_START / INVALID_GOAL, an
  // unrecognised goal, an exception): the message gives OMPL's status.
  kPlannerError,
  kStartInCollision,  // the body at the start overlaps an obstacle (unknown included)
  kGoalInCollision,   // the body at the goal overlaps an obstacle
  kGoalUnknown,       // the goal lies in unknown space and unknown_is_occupied
  kMapStale,          // no map, or the map is older than the pose by > max_map_age_s
  kBadInput,          // a pose that is not finite, a multirotor goal outside its altitudes
};
std::string_view to_string(PlanStatus s);

// Poses: position (m, world) and yaw (rad). A ground robot's z is not planned (its body
// sits at ground_body_center_z_m); the path carries the start's z.
struct PlanRequest {
  msg::Waypoint start;
  msg::Waypoint goal;
  int64_t pose_stamp_ns = 0;  // when the start pose was measured (sim or wall time)
};

struct PlanStats {
  double total_ms = 0;
  double solve_ms = 0;          // LazyPRM*
  size_t searches = 0;          // LazyPRM*'s A* searches over the roadmap (reusable_lazy_prm.hpp)
  bool search_cut = false;      // the time limit stopped the repair of a path found
  double simplify_ms = 0;       // shortcutting and the final check
  size_t roadmap_vertices = 0;  // after the query
  size_t roadmap_edges = 0;
  size_t collision_checks = 0;   // body-against-map tests in this query
  bool direct = false;           // the straight motion was free: no roadmap search
  bool roadmap_cleared = false;  // the roadmap was over roadmap_max_vertices and dropped
  double raw_length_m = 0;       // the roadmap's path, before shortcutting (state distance)
  double length_m = 0;           // the returned path (state-space distance)
  size_t guide_milestones = 0;   // guided sampling: grid-path poses added to the roadmap
  double guide_ms = 0;           // guided sampling (grid, search, checks)
};

struct PlanResult {
  PlanStatus status = PlanStatus::kBadInput;
  std::vector<msg::Waypoint> path;  // start first, goal last; empty unless kOk
  std::string message;              // why, for the log
  // The first failure with this status for this goal (the caller logs it; repeats are not)
  bool first_report = false;
  PlanStats stats;
};

// Travel distances from one pose to many (MotionPlanner::roadmap_distances).
struct RoadmapDistances {
  // kOk, or why `from` has none: kBadInput (not finite), kMapStale (no map yet),
  // kStartInCollision (its body overlaps an obstacle)
  PlanStatus status = PlanStatus::kBadInput;
  // per target: the length (m; x, y for a ground robot, x, y, z for a multirotor) of the
  // shortest path from `from` over the roadmap, or the straight motion where it is free;
  // +inf where the roadmap does not reach it, or the target is not a valid goal (not
  // finite, outside a multirotor's altitudes, unknown with unknown_is_occupied, body in
  // collision). Empty unless kOk.
  std::vector<double> distances_m;
  std::string message;  // why, unless kOk
  double ms = 0;
  double grow_ms = 0;           // of which growing a sparse roadmap
  size_t grown_vertices = 0;    // added to a sparse roadmap first
  size_t roadmap_vertices = 0;  // after the query
  size_t collision_checks = 0;  // body-against-map tests in this query
  size_t checked_edges = 0;     // roadmap edges checked (then cached or deleted)
  size_t removed_edges = 0;     // found invalid (and deleted, as LazyPRM does)
  size_t removed_vertices = 0;
};

struct MapUpdateStats {
  size_t changed_blocks = 0;
  bool rebuilt = false;
  size_t forgotten_vertices = 0;  // roadmap vertices / edges whose validity was reset
  size_t forgotten_edges = 0;
  double ms = 0;
};

class MotionPlanner {
 public:
  // Fails on an invalid config (the message names the key).
  static Result<MotionPlanner, std::string> create(const PlannerConfig& config);
  ~MotionPlanner();
  MotionPlanner(MotionPlanner&&) noexcept;
  MotionPlanner& operator=(MotionPlanner&&) noexcept;

  // A new snapshot (non-null) and its stamp (the capture time of its newest depth image).
  MapUpdateStats update_map(std::shared_ptr<const tsdf::MapSnapshot> map, int64_t stamp_ns);

  PlanResult plan(const PlanRequest& request);

  // The travel distance from `from` to each target over the roadmap (one Dijkstra for all
  // of them; see RoadmapDistances). Yaws matter for a ground robot's ellipse: the motions
  // leave `from` and reach each target in their yaw. No map-age check (no pose stamp).
  RoadmapDistances roadmap_distances(const msg::Waypoint& from,
                                     const std::vector<msg::Waypoint>& targets);

  // Whether the body at this pose is clear of the current map's obstacles (false without a
  // map).
  bool is_free(const msg::Waypoint& pose) const;
  // Teammates parked for good (lost: a dead process leaves its robot where it stood, and the
  // maps never held it): discs (ground robots, in the plane) or balls of radius_m around
  // `centers` that the body keeps clear of, in every query and in is_free(). The roadmap
  // re-checks what it knew valid near a new one.
  void set_parked(std::vector<Eigen::Vector3d> centers, double radius_m);
  // Drops the roadmap (the next query builds a new one).
  void clear_roadmap();
  size_t roadmap_vertices() const;
  const PlannerConfig& config() const;
  const robot::BodyModel& body() const;

 private:
  struct Impl;
  explicit MotionPlanner(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::motion
