#pragma once

// Guided sampling for a ground robot's LazyPRM* (a deviation from the thesis's plain
// LazyPRM*, 2.5.3; docs/low_level_planner.md "Guided sampling"): a 2D grid search over the
// map's body-height slab finds a likely corridor from the start to the goal, and poses along
// it (yaw along the corridor) are added to the roadmap as milestones before LazyPRM* runs.
// On a partly unknown parking-lot map, uniform samples alone needed thousands of vertices
// before the elongated body found its way through the narrow known-free passages.
//
// The grid is the map's voxel grid in x, y. A cell is blocked when a voxel of its slab
// [z_lo, z_hi] is occupied, or (with unknown_is_occupied) when one is unknown; a cell is
// passable when no blocked cell lies within `clearance_m` of its centre (the body's smallest
// horizontal semi-axis: a necessary condition for the body to fit, not a sufficient one, so
// the guide only proposes; LazyPRM* checks every pose and motion as before). A* over the
// 8-connected passable cells (Euclidean steps, octile heuristic).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::motion {

struct GuideConfig {
  double z_lo_m = 0.15;  // the body's vertical extent (centre height ± vertical semi-axis)
  double z_hi_m = 0.85;
  double clearance_m = 0.35;  // free radius a cell needs: the body's smaller horizontal semi-axis
  double spacing_m = 0.65;    // between the poses put on the roadmap
  bool unknown_is_occupied = true;
};

// A pose on the guide: x, y (m) and the corridor's direction (rad).
struct GuidePose {
  double x = 0, y = 0, yaw = 0;
};

// The passable cells of one map over a box, kept between queries on the same map.
class GuideGrid {
 public:
  // Classifies the cells of `bounds` (x, y; m) on `map`.
  GuideGrid(const tsdf::MapSnapshot& map, const Eigen::AlignedBox2d& bounds,
            const GuideConfig& config);

  // Poses every spacing_m along the shortest passable grid path from `start` to `goal`
  // (both excluded), or none when the grid does not connect them (or either lies outside
  // the box). The start's and the goal's own cells are passable by fiat: the caller has
  // checked the body there.
  std::vector<GuidePose> search(const Eigen::Vector2d& start, const Eigen::Vector2d& goal) const;

  uint64_t map_sequence() const { return map_sequence_; }
  const Eigen::AlignedBox2d& bounds() const { return bounds_; }
  size_t cells() const { return passable_.size(); }

 private:
  bool cell_of(const Eigen::Vector2d& p, Eigen::Vector2i& c) const;

  GuideConfig config_;
  Eigen::AlignedBox2d bounds_;
  uint64_t map_sequence_ = 0;
  double voxel_m_ = 0;
  Eigen::Vector2i origin_ = Eigen::Vector2i::Zero();  // voxel index of cell (0, 0)
  int nx_ = 0, ny_ = 0;
  std::vector<uint8_t> passable_;  // nx_ * ny_, row-major in y
};

}  // namespace scancrew::motion
