#pragma once

// The peer of `scancrew bench tsdf`: Open3D's ScalableTSDFVolume (Open3D 0.16, the CPU
// "legacy" pipeline) on the same frames and poses. Plain types only here: Open3D's headers
// stay in open3d_peer.cpp (they take ~4 s to parse, and open3d/utility/Logging.h defines
// global macros that break other headers). Built only when CMake finds Open3D
// (SCANCREW_WITH_OPEN3D).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "sim/mesh_io.hpp"

namespace scancrew::bench {

struct PeerCamera {
  uint32_t width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // u = fx·x/z + cx
};

struct PeerFrame {
  const float* depth_m = nullptr;        // width·height, row-major; NaN = no measurement
  std::array<double, 16> T_cam_world{};  // row-major 4×4, world → camera (optical frame)
};

struct PeerConfig {
  double voxel_m = 0.2;
  double truncation_m = 0.6;  // sdf_trunc
  double max_range_m = 5.0;   // depth_trunc: farther depth is dropped
};

struct PeerRun {
  std::vector<double> integrate_ms;  // per frame: Integrate() only
  std::vector<double> prepare_ms;    // per frame: the RGBDImage made from the depth
  double mesh_ms = 0;                // ExtractTriangleMesh()
  io::TriangleMesh mesh;
  size_t volume_units = 0;
  size_t voxels_per_unit = 0;
  size_t memory_bytes = 0;  // volume units × resolution³ × sizeof(TSDFVoxel)
};

// "Open3D 0.16.1 ScalableTSDFVolume (volume units of 16³ voxels, depth stride 4)"
std::string open3d_description();
// The number of OpenMP threads Open3D runs with.
int open3d_threads();

// Integrates the frames into a fresh ScalableTSDFVolume (no colour) and extracts its mesh.
// Errors: Open3D's exceptions, as text.
Result<PeerRun, std::string> run_open3d(const PeerCamera& camera, std::span<const PeerFrame> frames,
                                        const PeerConfig& config);

}  // namespace scancrew::bench
