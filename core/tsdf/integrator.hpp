#pragma once

// Integrator: projective integration of a depth image into a TsdfMap (thesis eq. 1.2,
// 1.3 with the 1/z² weight of 3.4.1), on all cores (TBB, one task per block).
//
// For each voxel centre p (camera frame) that projects to a pixel with a valid depth D
// (finite, within [min_range, max_range]; D and z along the optical axis):
// d = (D − z)·|p|/z, the distance from the voxel to the measured surface along the viewing
// ray (thesis 1.3.3, Fig. 1.2: "the distance of the sensor from v along the viewing ray,
// subtracted from the depth value"; Open3D's ScalableTSDFVolume measures the same);
// if d ≥ −μ:  φ_c = min(d, μ),  w_c = 1/|p|² (or 1),
//             φ ← (φ·w + φ_c·w_c)/(w + w_c),  w ← min(w + w_c, max_weight).
// So the whole ray in front of the surface is carved as empty (φ = μ), which the ISE
// (empty voxels next to unknown ones) and the planners' free space need.
//
// Block selection without per-pixel ray casting: the depth image is cut into tiles whose
// maximum depth is kept (one parallel read of the image, which also checks the pixels); a
// block of the view frustum's bounding box is integrated when the box of its voxel centres
// is in front of the camera and some tile under its image footprint sees at least as far
// as the box's near side less μ. Blocks allocated but left untouched are removed again.
//
// Bad input (the map is left unchanged): a size or buffer mismatch, intrinsics that are
// not finite and positive, a pose that is not a rigid transform, depth values that are
// infinite or negative. NaN is the "no measurement" marker of depth images and is skipped.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::tsdf {

struct DepthFrame {
  const float* depth_m =
      nullptr;      // row-major, width·height; NaN: no measurement, +inf: none in range
  size_t size = 0;  // elements behind depth_m
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

// Empty when the frame can be integrated, else the reason (integrate() checks the same,
// reading the image only once).
std::string check_frame(const DepthFrame& frame);

class Integrator {
 public:
  explicit Integrator(const TsdfConfig& config) : config_(config) {}

  // Integrates one frame as one map update (map.begin_update()).
  Result<IntegrationStats, std::string> integrate(TsdfMap& map, const DepthFrame& frame);

 private:
  struct BlockWork {
    Block* block = nullptr;
    BlockIndex index;
    bool fresh = false;
    uint32_t updated = 0;
  };
  std::string scan_tiles(const DepthFrame& frame);
  void select_blocks(const DepthFrame& frame, float frame_max);
  void touch_blocks(TsdfMap& map);
  void integrate_blocks(const DepthFrame& f, uint64_t sequence);

  TsdfConfig config_;
  int tiles_x_ = 0, tiles_y_ = 0;
  std::vector<float> tile_max_;
  std::vector<size_t> first_bad_;  // per tile row
  std::vector<uint8_t> selected_;  // per block of the frustum's bounding box
  std::vector<BlockIndex> candidates_;
  std::vector<BlockWork> work_;
};

}  // namespace scancrew::tsdf
