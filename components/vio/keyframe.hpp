#pragma once

// Keyframe: the reference of eVO's tracking (thesis 1.2.2) — a stereo pair's triangulated
// corners, kept until too few of them are still tracked; and Tracks, where those corners
// are in the latest image. The pose of every frame is computed against the keyframe, so
// drift grows per keyframe, not per frame.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "interfaces/geometry.hpp"

namespace scancrew::vio {

struct Keyframe {
  uint64_t id = 0;
  int64_t stamp_ns = 0;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  msg::CameraIntrinsics intrinsics;
  std::vector<Eigen::Vector3d> points_cam;  // m, this keyframe's left optical frame
};

// Parallel arrays: track i is keyframe point `point[i]`, seen at `px[i]` in the latest image.
struct Tracks {
  std::vector<uint32_t> point;
  std::vector<Eigen::Vector2f> px;

  size_t size() const { return point.size(); }
  void clear() {
    point.clear();
    px.clear();
  }
  // Keeps the tracks whose flag is set, in order.
  void keep_if(const std::vector<uint8_t>& flag) {
    size_t n = 0;
    for (size_t i = 0; i < point.size(); ++i) {
      if (flag[i] == 0) continue;
      point[n] = point[i];
      px[n] = px[i];
      ++n;
    }
    point.resize(n);
    px.resize(n);
  }
};

}  // namespace scancrew::vio
