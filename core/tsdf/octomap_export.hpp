#pragma once

// OctoMap export (Hornung et al. 2013): the TSDF's known space as an octomap::OcTree in
// OctoMap's binary format (.bt, maximum-likelihood occupancy), for planners and viewers
// that read OctoMap (octovis, ROS).
//
// The octree's resolution is the voxel size and its leaves coincide with the voxels
// (OctoMap key k covers [(k − 2¹⁵)·r, (k − 2¹⁵ + 1)·r) per axis, as voxel k − 2¹⁵ does).
// Every known voxel (w ≥ W_th) becomes a leaf: occupied (φ ≤ 0) or free; unknown voxels
// stay unknown. Leaves outside the key range (beyond ±2¹⁵ voxels from the origin) are
// skipped and counted.

#include <cstddef>
#include <string>

#include "core/result.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::tsdf {

struct OctomapStats {
  size_t occupied = 0;      // voxels written as occupied
  size_t free = 0;          // voxels written as free
  size_t out_of_range = 0;  // known voxels outside OctoMap's key range, skipped
  size_t leaf_nodes = 0;    // leaves of the pruned octree
  size_t bytes = 0;         // size of the file written
};

// Writes the snapshot's known space to path (replacing it). On failure, a message naming
// the path and the system's reason. Builds the whole octree in memory first.
Result<OctomapStats, std::string> write_octomap(const MapSnapshot& snap, const std::string& path);

}  // namespace scancrew::tsdf
