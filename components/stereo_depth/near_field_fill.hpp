#pragma once

// Near-field fill: invalid depth just beyond the floor a ground robot's camera sees is an
// obstacle there. Stereo matching finds no disparity on a plain (textureless) face, so a
// painted wall ahead leaves NaN depth, the map never gets it, and a planner that takes
// unknown space as free drives into it (docs/low_level_planner.md, "Plain surfaces").
//
// Per image column, from the bottom row up (the free-space boundary of the stixel world:
// Badino, Franke, Pfeiffer, "The Stixel World", DAGM 2009, taken to invalid pixels):
//   - a row whose ray meets the floor nearer than `blind_range_m` (the matcher's least depth)
//     is skipped: it is NaN whatever is there;
//   - a valid pixel within `floor_tolerance_m` of the floor plane is floor seen free; any
//     other valid pixel is a surface seen, the map has it, and the column is done;
//   - an invalid pixel after floor was seen starts a run. Its ray would have met the floor at
//     depth D. When D <= `range_m` and the run goes on, with no valid pixel, up to the rows
//     whose rays would meet the floor at `confirm_factor`·D or beyond (or above the horizon),
//     the floor ends at D behind something unseen: the run's pixels get depth D up to
//     `max_height_m` above the floor (a fronto-parallel face at the floor's end, no higher
//     than a ground robot can hit). A shorter run is a hole in the floor's match.
// A textured scene gives a valid surface where the floor ends and is left as it is; a column
// with no floor seen (a face nearer than the blind range) is left too: the obstacle was
// filled in earlier frames, when it was farther, and filling it at the blind range would
// carve free space through it. Known limits: an overhang above floor that is seen free, a
// plain floor (nothing is filled: the floor is never seen), a plain object lower than
// about a third of the camera height (its run is too short).
//
// Plain function, no allocation, deterministic; any thread.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "interfaces/geometry.hpp"

namespace scancrew::stereo_depth {

struct NearFieldFillConfig {
  double range_m = 1.5;            // the near field (depth of the floor's end); 0: off
  double confirm_factor = 1.5;     // the run must reach rays meeting the floor this much farther
  double floor_tolerance_m = 0.1;  // a valid point this near the floor plane is floor
  double max_height_m = 0.5;       // filled up to this height above the floor
  // Empty when valid, else every problem, "; "-separated.
  std::string validate() const;
};

struct NearFieldFillStats {
  uint32_t columns = 0;  // columns filled
  uint32_t pixels = 0;   // pixels given a depth
};

// Fills `depth_m` (width·height, m along the optical axis, NaN = unknown) in place.
// T_floor_cam: the camera's optical frame (z forward, x right, y down) in a frame whose
// z = 0 plane is the floor, z up (a ground robot's body frame). blind_range_m: the least
// depth the matcher can give.
NearFieldFillStats fill_near_field(std::vector<float>& depth_m, const msg::CameraIntrinsics& K,
                                   const Eigen::Isometry3d& T_floor_cam, double blind_range_m,
                                   const NearFieldFillConfig& config);

}  // namespace scancrew::stereo_depth
