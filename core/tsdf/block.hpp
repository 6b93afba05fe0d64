#pragma once

// The TSDF's storage unit: a block of kBlockSide³ voxels, addressed by integer block
// coordinates (voxel hashing, Nießner et al. 2013; thesis 1.3.2). Only observed blocks
// exist, so memory grows with the observed space, not with the scene's bounding box.
//
// A voxel holds the truncated signed distance in metres, clamped to [−μ, μ] (the thesis's
// normalised φ of eq. 1.3 is distance / μ), and its accumulated weight (eq. 1.2). Its
// state (thesis eq. 1.1 with W_th): unknown when w < W_th, else occupied when φ ≤ 0 and
// empty when φ > 0.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace scancrew::tsdf {

inline constexpr int kBlockSide = 8;  // voxels per block edge
inline constexpr int kBlockVoxels = kBlockSide * kBlockSide * kBlockSide;

struct Voxel {
  float distance_m = 0;
  float weight = 0;
};

enum class VoxelState : uint8_t { kUnknown, kEmpty, kOccupied };

inline VoxelState state_of(const Voxel& v, float w_th) {
  if (!(v.weight >= w_th)) return VoxelState::kUnknown;
  return v.distance_m <= 0 ? VoxelState::kOccupied : VoxelState::kEmpty;
}

struct Block {
  std::array<Voxel, kBlockVoxels> voxels{};
  uint64_t modified = 0;  // the map's update sequence number when last written
  uint32_t owner = 0;     // robot id that contributed most weight (0: unknown / own)

  static constexpr int index(int x, int y, int z) { return x + kBlockSide * (y + kBlockSide * z); }
  Voxel& at(int x, int y, int z) { return voxels[static_cast<size_t>(index(x, y, z))]; }
  const Voxel& at(int x, int y, int z) const { return voxels[static_cast<size_t>(index(x, y, z))]; }
};

using BlockIndex = Eigen::Vector3i;  // block coordinates
using VoxelIndex = Eigen::Vector3i;  // global voxel coordinates

struct BlockIndexHash {
  size_t operator()(const BlockIndex& b) const {
    // three large primes (Teschner et al. 2003), the usual spatial hash
    return static_cast<size_t>(b.x()) * 73856093u ^ static_cast<size_t>(b.y()) * 19349669u ^
           static_cast<size_t>(b.z()) * 83492791u;
  }
};

// Floor division for negative coordinates: the block holding global voxel v.
inline BlockIndex block_of(const VoxelIndex& v) {
  auto div = [](int a) { return a >= 0 ? a / kBlockSide : -((-a + kBlockSide - 1) / kBlockSide); };
  return {div(v.x()), div(v.y()), div(v.z())};
}
// The voxel's coordinates inside its block, 0..kBlockSide-1.
inline Eigen::Vector3i local_of(const VoxelIndex& v) {
  auto mod = [](int a) { return ((a % kBlockSide) + kBlockSide) % kBlockSide; };
  return {mod(v.x()), mod(v.y()), mod(v.z())};
}
// The global voxel holding world point p.
inline VoxelIndex voxel_of(const Eigen::Vector3d& p, double voxel_m) {
  return {static_cast<int>(std::floor(p.x() / voxel_m)),
          static_cast<int>(std::floor(p.y() / voxel_m)),
          static_cast<int>(std::floor(p.z() / voxel_m))};
}
inline Eigen::Vector3d voxel_center(const VoxelIndex& v, double voxel_m) {
  return (v.cast<double>() + Eigen::Vector3d::Constant(0.5)) * voxel_m;
}

}  // namespace scancrew::tsdf
