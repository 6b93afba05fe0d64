#pragma once

// Map messages: TSDF patches (thesis 4.4.1), patch lists and requests, ISE sets (2.4.2)
// and viewpoint clusters (2.4.3).

#include <cstdint>
#include <vector>

#include "interfaces/geometry.hpp"
#include "interfaces/header.hpp"
#include "interfaces/nav_msgs.hpp"  // Waypoint

namespace scancrew::msg {

// A TSDF voxel: truncated signed distance (m) and accumulated weight.
struct TsdfVoxel {
  float distance_m = 0;
  float weight = 0;
};

// One patch of a robot's manifold map: a dense block of voxels in the patch's own frame.
struct TsdfPatch {
  static constexpr const char* kTypeName = "scancrew/TsdfPatch";
  Header header;
  uint64_t patch_id = 0;  // (robot id << 32) | local counter
  Pose3 T_world_patch;
  double voxel_size_m = 0;
  uint32_t size_x = 0, size_y = 0, size_z = 0;
  std::vector<TsdfVoxel> voxels;  // size_x*size_y*size_z, x fastest
};

// The IDs of the patches a robot holds (broadcast so others can ask for the missing).
struct PatchList {
  static constexpr const char* kTypeName = "scancrew/PatchList";
  Header header;
  std::vector<uint64_t> patch_ids;
};

struct PatchRequest {
  static constexpr const char* kTypeName = "scancrew/PatchRequest";
  Header header;
  uint32_t from_robot = 0;
  std::vector<uint64_t> patch_ids;
};

// Incomplete Surface Elements: voxel centres and the view direction of each.
struct IseSet {
  static constexpr const char* kTypeName = "scancrew/IseSet";
  Header header;
  uint64_t map_version = 0;
  std::vector<Vec3> centers_m;
  std::vector<Vec3> view_directions;  // unit vectors
};

struct Viewpoint {
  Waypoint pose;
  std::vector<uint32_t> seen_ise;  // indices into the IseSet
};

struct ViewpointCluster {
  uint32_t id = 0;
  double gain = 0;  // g(U) = |C_U| / |C|
  std::vector<Viewpoint> viewpoints;
};

struct ViewpointClusters {
  static constexpr const char* kTypeName = "scancrew/ViewpointClusters";
  Header header;
  uint64_t map_version = 0;
  std::vector<ViewpointCluster> clusters;
};

}  // namespace scancrew::msg
