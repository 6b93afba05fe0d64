#pragma once

// The reachable ground truth: the ground-truth points (sim::sample_surfaces) that a robot kind
// can observe from some pose it can reach — so that coverage says what a team could see, not
// the top of a 5 m wall or a room behind a closed door.
//
// A point counts when, from some reachable body position (FreeSpace, eval/free_space.hpp;
// ground: a floor cell free for its footprint and connected to a start; multirotor: a cell of
// its altitude band), a camera turned to face it (yaw is free: robots turn; the camera stays
// level) sees it:
//   - the camera sits camera_up_m above the body origin (ground: the floor) and
//     camera_forward_m ahead of it, towards the point;
//   - range: its depth along the optical axis, the horizontal distance from the camera, is in
//     [min_range_m, max_range_m] (depth images are cut by depth, not by ray length);
//   - vertical field of view: its elevation from the camera is within ±fov_v_deg / 2;
//   - facing: the camera is on the side of the surface its normal points to, or either side
//     unless trust_normals (mesh windings are not reliable), |cos| > min_facing_cos;
//   - line of sight: the segment camera-point crosses no solid, mesh triangle or floor
//     (sim::SceneSolids::segment_blocked, end_margin_m at each end): this also rules out the
//     back of a solid's face.
//
// Approximation (for speed; the parking lot's 1.5 M points and the powerplant's 1.8 M take
// seconds, docs/evaluation.md): body positions are FreeSpace::reachable_positions on a
// lattice of pose_spacing_m, not every reachable pose; points are bucketed by (bucket_m
// voxel, normal octant); each bucket lists the positions that pass conservative range, field
// of view and facing tests for its whole voxel, nearest first; a point first tries the
// position that last served its bucket, then the exact tests on the bucket's list, and casts
// at most max_rays_per_point lines of sight (half to the nearest candidates, half spread over
// the rest). A point seen only from a pose between lattice positions, or only from candidates
// beyond the cap, counts as unobservable: the result errs on the side of "not observable".
//
// Thread safety: reachable_truth() runs on TBB's threads; the inputs are read only.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "eval/free_space.hpp"
#include "sim/robot_model.hpp"
#include "sim/scene_solids.hpp"
#include "sim/surface_sampler.hpp"

namespace scancrew::eval {

struct ObserverModel {
  double camera_forward_m = 0.25;  // ahead of the body origin, towards the point
  double camera_up_m = 0.35;  // above the body origin: ground, the floor; multirotor, its centre
  double min_range_m = 0.3, max_range_m = 5.0;  // depth along the optical axis
  double fov_v_deg = 60.0;                      // vertical field of view, around the horizon
  double min_facing_cos = 0.0;  // |cos| of the normal to the direction of the camera, above this
};

// The observer of a robot's camera (sim::CameraSpec: mount, range, vertical FOV).
ObserverModel observer_from_camera(const sim::CameraSpec& camera);

struct ReachableTruthOptions {
  double pose_spacing_m = 0;  // lattice of body positions; 0: 0.5 m ground, 1 m multirotor
  double bucket_m = 1.0;      // voxel of the point buckets
  int max_rays_per_point = 24;
  double end_margin_m = 1e-3;  // segment_blocked's margin at each end
  // true: a point is seen only from the side its normal points to (fewer candidates: faster).
  // sample_surfaces' normals of boxes, cylinders, walls, floor and ceiling are right; a
  // mesh's follow its triangles' winding, which the powerplant's does not keep consistent
  // (70 % of its points observable one-sided, 96 % two-sided). false: either side; the line of
  // sight rules out the inside of a solid.
  bool trust_normals = false;
};

struct ReachableTruth {
  std::vector<uint8_t> observable;  // one per point: 1 observable, 0 not
  size_t observable_count = 0;
  size_t poses = 0;    // body positions tried
  size_t buckets = 0;  // point buckets
  uint64_t rays = 0;   // lines of sight cast
};

// points and normals (unit, outward) of the same length. Errors: lengths that differ, an
// observer with max_range_m <= min_range_m or a field of view outside (0, 180), options
// that are not positive, a free space with no reachable cell.
Result<ReachableTruth, std::string> reachable_truth(
    const std::vector<std::array<float, 3>>& points,
    const std::vector<std::array<float, 3>>& normals, const sim::SceneSolids& solids,
    const FreeSpace& free_space, const ObserverModel& observer,
    const ReachableTruthOptions& options = {});

// The samples that are observable; area_m2 scaled by the fraction kept.
sim::SurfaceSamples observable_samples(const sim::SurfaceSamples& truth,
                                       const std::vector<uint8_t>& observable);

// From a scene file: its ground truth (sample_surfaces with `sampling`), its solids and
// meshes, the free space of `body` from `starts`, the reachable truth for `camera`.
struct SceneReachableTruth {
  sim::SurfaceSamples truth;  // every ground-truth point
  ReachableTruth reachable;   // which of them are observable
  size_t free_cells = 0, reachable_cells = 0;
  std::vector<bool> start_free;
  double seconds_free_space = 0, seconds_rays = 0;  // wall-clock
};
Result<SceneReachableTruth, std::string> scene_reachable_truth(
    const std::string& scene_path, const FreeSpaceBody& body, const std::vector<msg::Vec3>& starts,
    const sim::CameraSpec& camera, const sim::SamplingOptions& sampling = {},
    const ReachableTruthOptions& options = {});
// The same with default_body(kind) and a default sim::CameraSpec.
Result<SceneReachableTruth, std::string> scene_reachable_truth(
    const std::string& scene_path, robot::RobotKind kind, const std::vector<msg::Vec3>& starts,
    const sim::SamplingOptions& sampling = {});

}  // namespace scancrew::eval
