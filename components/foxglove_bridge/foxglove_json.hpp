#pragma once

// Our messages as Foxglove well-known messages, JSON-encoded (https://docs.foxglove.dev/docs/
// visualization/message-schemas): what the foxglove_bridge serves live, and what a recording
// can store as Foxglove channels (MCAP, "json" encoding, the schema named by schema_name()).
//
// Conventions: every pose is in the frame given (the bridge's "world"); a Waypoint's yaw is a
// rotation about z; timestamps are the messages' stamps (sim time, ns) as {sec, nsec};
// positions are rounded to the millimetre, to keep the JSON short. Entities of a SceneUpdate
// have a fixed id per kind ("ises", "clusters", "mesh"), so each update replaces the last.
// Thread safety: pure functions. Each allocates its result only.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/tsdf/mesher.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::foxglove {

enum class Schema : uint8_t {
  kPoseInFrame,
  kPosesInFrame,
  kSceneUpdate,
  kRawImage,
  kFrameTransforms
};

// "foxglove.PoseInFrame", ...: the schema's name (a channel's schemaName, MCAP's schema name).
std::string_view schema_name(Schema schema);
// The schema itself, JSON Schema text (foxglove_schemas.hpp).
std::string_view schema_text(Schema schema);

// {sec, nsec} of a time in ns (negative or unset stamps give 0).
nlohmann::json timestamp_json(int64_t stamp_ns);
nlohmann::json pose_json(const msg::Pose3& pose);
msg::Pose3 pose_of(const msg::Waypoint& waypoint);

// foxglove.PoseInFrame
nlohmann::json pose_in_frame(const msg::Pose3& pose, int64_t stamp_ns, std::string_view frame_id);
// foxglove.PosesInFrame
nlohmann::json poses_in_frame(std::span<const msg::Pose3> poses, int64_t stamp_ns,
                              std::string_view frame_id);
nlohmann::json local_path_json(const msg::LocalPath& path, std::string_view frame_id);
// A robot's tour: its viewpoints in visiting order.
nlohmann::json tour_json(const msg::PathSequence& tour, int64_t stamp_ns,
                         std::string_view frame_id);
// Every viewpoint of the clusters.
nlohmann::json viewpoints_json(const msg::ViewpointClusters& clusters, std::string_view frame_id);

// foxglove.SceneUpdate: a sphere at each cluster's centroid (radius grows with its gain) and
// its id as a text.
nlohmann::json clusters_json(const msg::ViewpointClusters& clusters, std::string_view frame_id);
// foxglove.SceneUpdate: a cube of voxel_size_m per ISE, red, grey for those in C_rem.
nlohmann::json ises_json(const msg::IseSet& ises, double voxel_size_m, std::string_view frame_id);
// foxglove.SceneUpdate: the mesh as one indexed triangle list.
nlohmann::json mesh_json(const tsdf::Mesh& mesh, int64_t stamp_ns, std::string_view frame_id);

// foxglove.RawImage: depth as 32FC1 (metres; NaN unknown, +inf beyond range, as REP 117).
nlohmann::json depth_image_json(const msg::DepthImage& depth, std::string_view frame_id);
// foxglove.RawImage: an 8-bit grey image (mono8), row-major.
nlohmann::json mono8_image_json(uint32_t width, uint32_t height, std::span<const uint8_t> pixels,
                                int64_t stamp_ns, std::string_view frame_id);

struct FrameTransform {
  int64_t stamp_ns = 0;
  std::string parent_frame_id, child_frame_id;
  msg::Pose3 T_parent_child;
};
// foxglove.FrameTransforms
nlohmann::json frame_transforms_json(std::span<const FrameTransform> transforms);

// RFC 4648 base64 (what the schemas' "contentEncoding": "base64" fields hold).
std::string base64(std::span<const uint8_t> bytes);

}  // namespace scancrew::foxglove
