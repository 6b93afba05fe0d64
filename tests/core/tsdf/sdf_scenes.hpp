#pragma once

// Scenes for the mesher and export tests: a TSDF configuration, a box written from its
// analytic signed distance, any signed distance field written into a map's blocks, and the
// camera of synthetic_depth.hpp looking at a wall. Header-only.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/tsdf/integrator.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "tests/core/tsdf/synthetic_depth.hpp"

namespace scancrew::tsdf::test {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

inline TsdfConfig config(double voxel_m) {
  TsdfConfig c;
  c.voxel_m = voxel_m;
  c.truncation_m = 3 * voxel_m;
  c.max_range_m = 5.0;
  c.max_weight = 1000;
  return c;
}

// An axis-aligned box, with its exact signed distance.
struct Box {
  Eigen::Vector3d centre{0.23, -0.41, 0.17};
  Eigen::Vector3d half{0.72, 0.55, 0.38};

  double sdf(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d q = (p - centre).cwiseAbs() - half;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  }
  // the outward direction of steepest ascent (central differences of the exact field)
  Eigen::Vector3d gradient(const Eigen::Vector3d& p) const {
    constexpr double kStep = 1e-5;
    Eigen::Vector3d g;
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[i] = kStep;
      g[i] = (sdf(p + e) - sdf(p - e)) / (2 * kStep);
    }
    return g.normalized();
  }
  double edge_length() const { return 8 * half.sum(); }
  double area() const {
    const Eigen::Vector3d s = 2 * half;
    return 2 * (s.x() * s.y() + s.y() * s.z() + s.z() * s.x());
  }
};

// Writes the signed distance (clamped to ±μ) with the given weight into every voxel of the
// blocks that meet [lo, hi] and lie within band of the surface (by their centre), as one
// map update; the blocks get the owner.
template <class Sdf>
void fill(TsdfMap& map, const Sdf& sdf, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
          float weight = 1, uint32_t owner = 0, double band = kInf) {
  const uint64_t sequence = map.begin_update();
  const double r = map.config().voxel_m, mu = map.config().truncation_m;
  const double block_m = r * kBlockSide;
  const BlockIndex b_lo = block_of(voxel_of(lo, r)), b_hi = block_of(voxel_of(hi, r));
  for (int bz = b_lo.z(); bz <= b_hi.z(); ++bz)
    for (int by = b_lo.y(); by <= b_hi.y(); ++by)
      for (int bx = b_lo.x(); bx <= b_hi.x(); ++bx) {
        const BlockIndex b(bx, by, bz);
        const Eigen::Vector3d centre =
            (b.cast<double>() + Eigen::Vector3d::Constant(0.5)) * block_m;
        if (std::abs(sdf(centre)) > band + block_m * std::sqrt(3.0) / 2) continue;
        Block& block = map.touch(b);
        for (int z = 0; z < kBlockSide; ++z)
          for (int y = 0; y < kBlockSide; ++y)
            for (int x = 0; x < kBlockSide; ++x) {
              const double d = sdf(voxel_center(b * kBlockSide + Eigen::Vector3i(x, y, z), r));
              Voxel& v = block.at(x, y, z);
              v.distance_m = static_cast<float>(std::clamp(d, -mu, mu));
              v.weight = weight;
            }
        block.modified = sequence;
        block.owner = owner;
      }
}

inline std::vector<BlockIndex> indices(const TsdfMap& map) {
  std::vector<BlockIndex> out;
  for (const auto& entry : map.blocks()) out.push_back(entry.first);
  return out;
}

inline TsdfMap box_map(const Box& box, double voxel_m = 0.05) {
  TsdfMap map(config(voxel_m));
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(0.4);
  fill(
      map, [&](const Eigen::Vector3d& p) { return box.sdf(p); }, box.centre - box.half - margin,
      box.centre + box.half + margin);
  return map;
}

// The camera at the origin looking along +x (synthetic_depth.hpp).
inline DepthFrame wall_frame(const std::vector<float>& depth) {
  return frame(depth);
}

}  // namespace scancrew::tsdf::test
