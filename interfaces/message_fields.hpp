#pragma once

// visit_fields(message, visitor): calls visitor(field1, field2, ...) with every data member
// of a message or of a type a message holds, in declaration order. The codec
// (interfaces/codec.hpp) is built on it. Each visitor is a structured binding, so adding a
// member to a struct without listing it here does not compile: the wire format cannot
// silently miss a field. When a message changes, bump kMessageFormatVersion.

#include <string_view>
#include <utility>

#include "interfaces/geometry.hpp"
#include "interfaces/header.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::msg {

// Version of the binary layout of every message (recordings, inter-robot links). A reader
// refuses data of another version.
// 2: TsdfPatch carries the compact patch payload instead of a dense voxel array.
// 5: RobotState says whether the robot backs off and which teammate holds it.
// 6: ReplanRequest.
inline constexpr uint32_t kMessageFormatVersion = 6;

// The binding names only label the members; their order is the declaration order.
#define SCANCREW_MESSAGE_FIELDS(Type, ...)      \
  template <class V>                            \
  void visit_fields(Type& m, V&& visit) {       \
    auto& [__VA_ARGS__] = m;                    \
    visit(__VA_ARGS__);                         \
  }                                             \
  template <class V>                            \
  void visit_fields(const Type& m, V&& visit) { \
    const auto& [__VA_ARGS__] = m;              \
    visit(__VA_ARGS__);                         \
  }

SCANCREW_MESSAGE_FIELDS(Header, robot_id, seq, stamp_ns, publish_mono_ns)
SCANCREW_MESSAGE_FIELDS(Vec3, x, y, z)
SCANCREW_MESSAGE_FIELDS(Quat, w, x, y, z)
SCANCREW_MESSAGE_FIELDS(Pose3, position, orientation)
SCANCREW_MESSAGE_FIELDS(CameraIntrinsics, width, height, fx, fy, cx, cy)

SCANCREW_MESSAGE_FIELDS(StereoFrame, header, intrinsics, baseline_m, T_body_cam, left, right)
SCANCREW_MESSAGE_FIELDS(Imu, header, linear_acceleration_mps2, angular_velocity_radps)
SCANCREW_MESSAGE_FIELDS(DepthImage, header, intrinsics, T_world_cam, min_range_m, max_range_m,
                        depth_m)

SCANCREW_MESSAGE_FIELDS(Odometry, header, T_world_body, linear_velocity_mps, angular_velocity_radps,
                        pose_covariance, tracking_quality, tracking_resets)
SCANCREW_MESSAGE_FIELDS(Waypoint, position, yaw_rad)
SCANCREW_MESSAGE_FIELDS(LocalPath, header, plan_id, waypoints)
SCANCREW_MESSAGE_FIELDS(PathSequence, robot_id, cluster_ids, cluster_utilities, viewpoints,
                        viewpoint_clusters, ise_centers_m, utility)
SCANCREW_MESSAGE_FIELDS(TeamPlan, header, plan_id, map_version, sequences, unassigned)
SCANCREW_MESSAGE_FIELDS(VelocityCommand, header, linear_mps, yaw_rate_radps)
SCANCREW_MESSAGE_FIELDS(Maneuver, header, kind, aside, because_of_robot)
SCANCREW_MESSAGE_FIELDS(RobotState, header, T_world_body, velocity_mps, mode, plan_id,
                        current_cluster, path_index, steps_remaining, path_length_m, backing_off,
                        held_by_robot)
SCANCREW_MESSAGE_FIELDS(ReplanRequest, header, reason, because_of_robot, after_plan_id, repeated)
SCANCREW_MESSAGE_FIELDS(MissionStatus, header, phase, ise_remaining, coverage_estimate, elapsed_s)
SCANCREW_MESSAGE_FIELDS(StepMark, robot_id, topic_key, seq)
SCANCREW_MESSAGE_FIELDS(StepSync, header, t_ns, stop, marks)

SCANCREW_MESSAGE_FIELDS(TsdfPatch, header, patch_id, robot_id, index, T_world_patch, voxel_size_m,
                        truncation_m, block_count, raw_bytes, data)
SCANCREW_MESSAGE_FIELDS(PatchList, header, patch_ids)
SCANCREW_MESSAGE_FIELDS(PatchRequest, header, from_robot, patch_ids)
SCANCREW_MESSAGE_FIELDS(IseSet, header, map_version, centers_m, view_directions, remaining,
                        inspectable, complete)
SCANCREW_MESSAGE_FIELDS(Viewpoint, pose, seen_ise, robot_types)
SCANCREW_MESSAGE_FIELDS(ViewpointCluster, id, gain, viewpoints, robot_types, centroid)
SCANCREW_MESSAGE_FIELDS(ViewpointClusters, header, map_version, clusters, ise_count)

#undef SCANCREW_MESSAGE_FIELDS

// Every message type that can cross a process boundary (recordings, links between robots).
template <class... T>
struct TypeList {};
using WireMessages =
    TypeList<StereoFrame, Imu, DepthImage, Odometry, LocalPath, TeamPlan, VelocityCommand, Maneuver,
             RobotState, ReplanRequest, MissionStatus, TsdfPatch, PatchList, PatchRequest, IseSet,
             ViewpointClusters, StepSync>;

// Calls fn.template operator()<T>() for the wire message whose kTypeName is type_name;
// false when there is none.
template <class Fn, class... T>
bool with_message_type(std::string_view type_name, Fn&& fn, TypeList<T...> /*types*/ = {}) {
  return ((type_name == T::kTypeName ? (fn.template operator()<T>(), true) : false) || ...);
}
template <class Fn>
bool with_wire_message(std::string_view type_name, Fn&& fn) {
  return with_message_type(type_name, std::forward<Fn>(fn), WireMessages{});
}

}  // namespace scancrew::msg
