#pragma once

// Integrator: projective integration of a depth image into a TsdfMap (thesis eq. 1.2,
// 1.3 with the 1/z² weight of 3.4.1), on all cores (TBB, one task per block).
//
// For each voxel centre p (camera frame) that projects to a pixel with a valid depth D
// (finite, within [min_range, max_range]): d = D − z (z along the optical axis, as D);
// if d ≥ −μ:  φ_c = min(d, μ),  w_c = 1/|p|² (or 1),
//             φ ← (φ·w + φ_c·w_c)/(w + w_c),  w ← min(w + w_c, max_weight).
// So the whole ray in front of the surface is carved as empty (φ = μ), which the ISE
// (empty voxels next to unknown ones) and the planners' free space need.
//
// Block selection without per-pixel ray casting: the depth image is cut into tiles whose
// maximum depth is kept; a block of the view frustum's bounding box is integrated when its
// bounding sphere is in front of the camera and some tile under its image footprint sees
// at least as far as the block's near side less μ. Blocks allocated but left untouched
// are removed again.
//
// Bad input (the map is left unchanged): a size or buffer mismatch, intrinsics that are
// not finite and positive, a pose that is not a rigid transform, depth values that are
// infinite or negative. NaN is the "no measurement" marker of depth images and is skipped.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "components/tsdf/tsdf_map.hpp"
#include "executors/result.hpp"

namespace scancrew::tsdf {

struct DepthFrame {
  const float* depth_m = nullptr;  // row-major, width·height; NaN = no measurement
  size_t size = 0;                 // elements behind depth_m
  uint32_t width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixel (u, v) is at u = fx·x/z + cx
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
};

struct IntegrationStats {
  size_t candidate_blocks = 0;  // blocks of the frustum that passed the tile test
  size_t updated_blocks = 0;    // blocks with at least one voxel written
  size_t new_blocks = 0;        // of those, allocated by this frame
  size_t updated_voxels = 0;
};

// Empty when the frame can be integrated, else the reason.
std::string check_frame(const DepthFrame& frame);

class Integrator {
 public:
  explicit Integrator(const TsdfConfig& config) : config_(config) {}

  // Integrates one frame as one map update (map.begin_update()).
  Result<IntegrationStats, std::string> integrate(TsdfMap& map, const DepthFrame& frame);

 private:
  TsdfConfig config_;
  std::vector<float> tile_max_;
  std::vector<BlockIndex> candidates_;
};

}  // namespace scancrew::tsdf
