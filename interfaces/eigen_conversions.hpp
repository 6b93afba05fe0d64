#pragma once

// Message geometry <-> Eigen, for the components that compute with poses (perception,
// mapping, planning). Messages stay plain structs; algorithms use Eigen.

#include <Eigen/Geometry>
#include <cmath>

#include "interfaces/geometry.hpp"

namespace scancrew::msg {

inline Eigen::Vector3d to_eigen(const Vec3& v) {
  return {v.x, v.y, v.z};
}
inline Eigen::Quaterniond to_eigen(const Quat& q) {
  return Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized();
}
inline Eigen::Isometry3d to_eigen(const Pose3& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = to_eigen(p.orientation).toRotationMatrix();
  t.translation() = to_eigen(p.position);
  return t;
}

inline Vec3 to_msg(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}
inline Quat to_msg(const Eigen::Quaterniond& q) {
  const Eigen::Quaterniond n = q.normalized();
  return {n.w(), n.x(), n.y(), n.z()};
}
inline Pose3 to_msg(const Eigen::Isometry3d& t) {
  return {to_msg(Eigen::Vector3d(t.translation())), to_msg(Eigen::Quaterniond(t.rotation()))};
}

// The heading of an orientation: the body x axis's angle in the world's xy plane (rad).
inline double yaw_of(const Quat& q) {
  const Eigen::Matrix3d r = to_eigen(q).toRotationMatrix();
  return std::atan2(r(1, 0), r(0, 0));
}

}  // namespace scancrew::msg
