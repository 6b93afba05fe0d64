#pragma once

// Map messages: TSDF patches (thesis 4.4.1), patch lists and requests, ISE sets (2.4.2)
// and viewpoint clusters (2.4.3).

#include <cstdint>
#include <vector>

#include "interfaces/geometry.hpp"
#include "interfaces/header.hpp"
#include "interfaces/nav_msgs.hpp"  // Waypoint

namespace scancrew::msg {

// One patch of a robot's manifold map (thesis 4.4.1): the blocks a few consecutive depth
// maps observed, in the compact wire format of core/tsdf/patch_codec.hpp (observed
// blocks only, quantised distance and weight, zstd with a content checksum). The voxels stay
// on the world lattice (block coordinates in the world frame); T_world_patch, the pose of
// the patch's first depth map, is the patch's frame, kept for map deformation.
struct TsdfPatch {
  static constexpr const char* kTypeName = "scancrew/TsdfPatch";
  Header header;
  uint64_t patch_id = 0;  // (robot_id << 32) | index
  uint32_t robot_id = 0;  // the robot whose depth maps built the patch
  uint32_t index = 0;     // the patch's number among that robot's patches
  Pose3 T_world_patch;
  double voxel_size_m = 0;
  double truncation_m = 0;    // μ: the distances are quantised over [−μ, μ]
  uint32_t block_count = 0;   // blocks in the payload
  uint32_t raw_bytes = 0;     // payload size before compression
  std::vector<uint8_t> data;  // the zstd-compressed payload
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

// Incomplete Surface Elements (thesis Definition 1): voxel centres and the view direction
// of each (zero where it is undefined); C_rem (Definitions 2, 4) and the completion state.
struct IseSet {
  static constexpr const char* kTypeName = "scancrew/IseSet";
  Header header;
  uint64_t map_version = 0;  // the map snapshot's update sequence
  std::vector<Vec3> centers_m;
  std::vector<Vec3> view_directions;  // unit vectors
  std::vector<uint32_t> remaining;    // C_rem: indices of ISEs no robot type can scan
  uint32_t inspectable = 0;           // |C_ins| = |C| − |C_rem|
  uint8_t complete = 0;  // 1: C_ins empty over the configured consecutive updates (a byte, not
                         // a bool: any decoded byte is a valid value)
};

// Robot kinds as bits (core/robot/robot_kind.hpp, kind_bit).
inline constexpr uint32_t kGroundRobotBit = 1u, kMultirotorBit = 2u;

struct Viewpoint {
  Waypoint pose;                   // camera position and yaw
  std::vector<uint32_t> seen_ise;  // indices into the IseSet
  uint32_t robot_types = 0;        // bits of the robot types that can stand there
};

struct ViewpointCluster {
  uint32_t id = 0;
  double gain = 0;  // g(U) = |C_U| / |C|
  std::vector<Viewpoint> viewpoints;
  uint32_t robot_types = 0;  // bits of the robot types that can reach it
  Vec3 centroid;
};

struct ViewpointClusters {
  static constexpr const char* kTypeName = "scancrew/ViewpointClusters";
  Header header;
  uint64_t map_version = 0;
  std::vector<ViewpointCluster> clusters;
  uint32_t ise_count = 0;  // |C|, the gains' denominator
};

}  // namespace scancrew::msg
