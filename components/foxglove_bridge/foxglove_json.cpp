#include "components/foxglove_bridge/foxglove_json.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "components/foxglove_bridge/foxglove_schemas.hpp"

namespace scancrew::foxglove {

namespace {

using nlohmann::json;

double mm(double v) {
  return std::round(v * 1000.0) / 1000.0;
}

json vec3_json(double x, double y, double z) {
  return {{"x", mm(x)}, {"y", mm(y)}, {"z", mm(z)}};
}

json quat_json(const msg::Quat& q) {
  return {{"x", q.x}, {"y", q.y}, {"z", q.z}, {"w", q.w}};
}

json color_json(double r, double g, double b, double a) {
  return {{"r", r}, {"g", g}, {"b", b}, {"a", a}};
}

json identity_pose() {
  return pose_json(msg::Pose3{});
}

// A SceneEntity with every array the schema requires, empty.
json scene_entity(std::string_view id, int64_t stamp_ns, std::string_view frame_id) {
  const json empty = json::array();
  return {{"timestamp", timestamp_json(stamp_ns)},
          {"frame_id", frame_id},
          {"id", id},
          {"lifetime", {{"sec", 0}, {"nsec", 0}}},
          {"frame_locked", false},
          {"metadata", empty},
          {"arrows", empty},
          {"cubes", empty},
          {"spheres", empty},
          {"cylinders", empty},
          {"lines", empty},
          {"triangles", empty},
          {"texts", empty},
          {"models", empty}};
}

json scene_update(json entity) {
  return {{"deletions", json::array()}, {"entities", json::array({std::move(entity)})}};
}

json raw_image(uint32_t width, uint32_t height, std::string_view encoding, uint32_t step,
               std::span<const uint8_t> bytes, int64_t stamp_ns, std::string_view frame_id) {
  return {{"timestamp", timestamp_json(stamp_ns)},
          {"frame_id", frame_id},
          {"width", width},
          {"height", height},
          {"encoding", encoding},
          {"step", step},
          {"data", base64(bytes)}};
}

}  // namespace

std::string_view schema_name(Schema schema) {
  switch (schema) {
    case Schema::kPoseInFrame:
      return "foxglove.PoseInFrame";
    case Schema::kPosesInFrame:
      return "foxglove.PosesInFrame";
    case Schema::kSceneUpdate:
      return "foxglove.SceneUpdate";
    case Schema::kRawImage:
      return "foxglove.RawImage";
    case Schema::kFrameTransforms:
      return "foxglove.FrameTransforms";
  }
  return "?";
}

std::string_view schema_text(Schema schema) {
  switch (schema) {
    case Schema::kPoseInFrame:
      return kPoseInFrameSchema;
    case Schema::kPosesInFrame:
      return kPosesInFrameSchema;
    case Schema::kSceneUpdate:
      return kSceneUpdateSchema;
    case Schema::kRawImage:
      return kRawImageSchema;
    case Schema::kFrameTransforms:
      return kFrameTransformsSchema;
  }
  return "";
}

json timestamp_json(int64_t stamp_ns) {
  const int64_t ns = std::max<int64_t>(stamp_ns, 0);
  return {{"sec", ns / 1'000'000'000}, {"nsec", ns % 1'000'000'000}};
}

json pose_json(const msg::Pose3& pose) {
  return {{"position", vec3_json(pose.position.x, pose.position.y, pose.position.z)},
          {"orientation", quat_json(pose.orientation)}};
}

msg::Pose3 pose_of(const msg::Waypoint& waypoint) {
  msg::Pose3 pose;
  pose.position = waypoint.position;
  pose.orientation = {.w = std::cos(waypoint.yaw_rad / 2), .z = std::sin(waypoint.yaw_rad / 2)};
  return pose;
}

json pose_in_frame(const msg::Pose3& pose, int64_t stamp_ns, std::string_view frame_id) {
  return {
      {"timestamp", timestamp_json(stamp_ns)}, {"frame_id", frame_id}, {"pose", pose_json(pose)}};
}

json poses_in_frame(std::span<const msg::Pose3> poses, int64_t stamp_ns,
                    std::string_view frame_id) {
  json list = json::array();
  for (const msg::Pose3& p : poses) list.push_back(pose_json(p));
  return {
      {"timestamp", timestamp_json(stamp_ns)}, {"frame_id", frame_id}, {"poses", std::move(list)}};
}

namespace {
json waypoint_poses(std::span<const msg::Waypoint> waypoints, int64_t stamp_ns,
                    std::string_view frame_id) {
  std::vector<msg::Pose3> poses;
  poses.reserve(waypoints.size());
  for (const msg::Waypoint& w : waypoints) poses.push_back(pose_of(w));
  return poses_in_frame(poses, stamp_ns, frame_id);
}
}  // namespace

json local_path_json(const msg::LocalPath& path, std::string_view frame_id) {
  return waypoint_poses(path.waypoints, path.header.stamp_ns, frame_id);
}

json tour_json(const msg::PathSequence& tour, int64_t stamp_ns, std::string_view frame_id) {
  return waypoint_poses(tour.viewpoints, stamp_ns, frame_id);
}

json viewpoints_json(const msg::ViewpointClusters& clusters, std::string_view frame_id) {
  std::vector<msg::Waypoint> all;
  for (const msg::ViewpointCluster& c : clusters.clusters)
    for (const msg::Viewpoint& v : c.viewpoints) all.push_back(v.pose);
  return waypoint_poses(all, clusters.header.stamp_ns, frame_id);
}

json clusters_json(const msg::ViewpointClusters& clusters, std::string_view frame_id) {
  json entity = scene_entity("clusters", clusters.header.stamp_ns, frame_id);
  for (const msg::ViewpointCluster& c : clusters.clusters) {
    msg::Pose3 at;
    at.position = c.centroid;
    const double d = 0.2 + 2.0 * std::sqrt(std::clamp(c.gain, 0.0, 1.0));
    entity["spheres"].push_back({{"pose", pose_json(at)},
                                 {"size", vec3_json(d, d, d)},
                                 {"color", color_json(0.2, 0.6, 1.0, 0.35)}});
    entity["texts"].push_back({{"pose", pose_json(at)},
                               {"billboard", true},
                               {"font_size", 14.0},
                               {"scale_invariant", true},
                               {"color", color_json(1, 1, 1, 1)},
                               {"text", std::to_string(c.id)}});
  }
  return scene_update(std::move(entity));
}

json ises_json(const msg::IseSet& ises, double voxel_size_m, std::string_view frame_id) {
  json entity = scene_entity("ises", ises.header.stamp_ns, frame_id);
  std::vector<bool> remaining(ises.centers_m.size(), false);
  for (const uint32_t i : ises.remaining)
    if (i < remaining.size()) remaining[i] = true;
  const json size = vec3_json(voxel_size_m, voxel_size_m, voxel_size_m);
  const json red = color_json(1.0, 0.15, 0.1, 0.9), grey = color_json(0.5, 0.5, 0.5, 0.6);
  for (size_t i = 0; i < ises.centers_m.size(); ++i) {
    msg::Pose3 at;
    at.position = ises.centers_m[i];
    entity["cubes"].push_back(
        {{"pose", pose_json(at)}, {"size", size}, {"color", remaining[i] ? grey : red}});
  }
  return scene_update(std::move(entity));
}

json mesh_json(const tsdf::Mesh& mesh, int64_t stamp_ns, std::string_view frame_id) {
  json entity = scene_entity("mesh", stamp_ns, frame_id);
  json points = json::array(), indices = json::array();
  for (const Eigen::Vector3f& v : mesh.vertices) points.push_back(vec3_json(v.x(), v.y(), v.z()));
  for (const tsdf::Triangle& t : mesh.triangles)
    for (const uint32_t i : t) indices.push_back(i);
  entity["triangles"].push_back({{"pose", identity_pose()},
                                 {"points", std::move(points)},
                                 {"color", color_json(0.75, 0.75, 0.7, 1.0)},
                                 {"colors", json::array()},
                                 {"indices", std::move(indices)}});
  return scene_update(std::move(entity));
}

json depth_image_json(const msg::DepthImage& depth, std::string_view frame_id) {
  const uint32_t w = depth.intrinsics.width, h = depth.intrinsics.height;
  std::span<const float> pixels(depth.depth_m.data(),
                                std::min<size_t>(depth.depth_m.size(), size_t{w} * h));
  const std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(pixels.data()),
                                       pixels.size_bytes());
  return raw_image(w, h, "32FC1", w * 4, bytes, depth.header.stamp_ns, frame_id);
}

json mono8_image_json(uint32_t width, uint32_t height, std::span<const uint8_t> pixels,
                      int64_t stamp_ns, std::string_view frame_id) {
  return raw_image(width, height, "mono8", width,
                   pixels.first(std::min<size_t>(pixels.size(), size_t{width} * height)), stamp_ns,
                   frame_id);
}

json frame_transforms_json(std::span<const FrameTransform> transforms) {
  json list = json::array();
  for (const FrameTransform& t : transforms) {
    const msg::Vec3& p = t.T_parent_child.position;
    list.push_back({{"timestamp", timestamp_json(t.stamp_ns)},
                    {"parent_frame_id", t.parent_frame_id},
                    {"child_frame_id", t.child_frame_id},
                    {"translation", vec3_json(p.x, p.y, p.z)},
                    {"rotation", quat_json(t.T_parent_child.orientation)}});
  }
  return {{"transforms", std::move(list)}};
}

std::string base64(std::span<const uint8_t> bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (uint32_t{bytes[i]} << 16) | (uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    for (const int shift : {18, 12, 6, 0}) out.push_back(kAlphabet[(v >> shift) & 63u]);
  }
  if (const size_t rest = bytes.size() - i; rest > 0) {
    const uint32_t v = (uint32_t{bytes[i]} << 16) | (rest == 2 ? uint32_t{bytes[i + 1]} << 8 : 0u);
    out.push_back(kAlphabet[(v >> 18) & 63u]);
    out.push_back(kAlphabet[(v >> 12) & 63u]);
    out.push_back(rest == 2 ? kAlphabet[(v >> 6) & 63u] : '=');
    out.push_back('=');
  }
  return out;
}

}  // namespace scancrew::foxglove
