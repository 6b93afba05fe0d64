#pragma once

// Tour: the cluster tour P^i a robot's low-level planner follows (thesis 2.5.3, Algorithms
// 1, 3 and 6: "foreach q ∈ Q, following P"): the path sequence from the high-level planner
// (msg::PathSequence), the index of the next viewpoint q, and C_start, the ISEs the tour was
// planned for, as voxel keys for UtilityCheck. Plain data and pure functions.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/motion/redundancy_check.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::low_level_planner {

using motion::TourProgress;

// The key of the voxel (of size voxel_m) holding a point: ISEs of two map updates are the
// same ISE when their centres fall in the same voxel.
uint64_t voxel_key(const msg::Vec3& p, double voxel_m);
// The sorted, unique keys of points.
std::vector<uint64_t> voxel_keys(std::span<const msg::Vec3> points, double voxel_m);

struct Tour {
  uint64_t plan_id = 0;  // of the msg::TeamPlan it came in
  msg::PathSequence sequence;
  size_t next = 0;                // the next viewpoint (sequence.viewpoints.size(): done)
  std::vector<uint64_t> c_start;  // sorted voxel keys of C_start
  size_t skipped = 0;             // viewpoints given up (no path to them)

  bool empty() const { return sequence.viewpoints.empty(); }
  bool done() const { return next >= sequence.viewpoints.size(); }
  const msg::Waypoint& goal() const { return sequence.viewpoints[next]; }
  uint32_t goal_cluster() const {
    return next < sequence.viewpoint_clusters.size() ? sequence.viewpoint_clusters[next] : 0;
  }
  size_t remaining() const { return done() ? 0 : sequence.viewpoints.size() - next; }
};

// The tour of `sequence` from plan `plan_id`, C_start keyed with the map's voxel size.
Tour make_tour(uint64_t plan_id, const msg::PathSequence& sequence, double voxel_m);

// The tour as RedundancyCheck sees it: one stop per viewpoint, with its cluster id.
TourProgress tour_progress(uint32_t robot_id, const msg::Vec3& position,
                           const msg::PathSequence& sequence, size_t next);

}  // namespace scancrew::low_level_planner
