#pragma once

// BoxWorld: a hand-built map for the planner tests — an observed region of voxels, free
// except where they touch one of the world's axis-aligned boxes (occupied), written
// straight into a TsdfMap (no rendering), and the same boxes as the ground truth
// (ObstacleGeometry). Voxels touching a box are occupied, so the map's obstacles contain
// the true ones. Boxes added later are written as a new map update: only their blocks
// change, as the integrator would do.
//
// occupied = {distance −v/2, weight 1}, free = {distance +v, weight 1}; W_th 0.5. Outside
// the observed region nothing is written: unknown.

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "core/motion/obstacle_geometry.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::motion::test {

class BoxWorld {
 public:
  BoxWorld(double voxel_m, const Eigen::AlignedBox3d& observed)
      : voxel_m_(voxel_m), observed_(observed), map_(config(voxel_m)) {}

  static tsdf::TsdfConfig config(double voxel_m) {
    tsdf::TsdfConfig c;
    c.voxel_m = voxel_m;
    c.truncation_m = 3 * voxel_m;
    c.w_th = 0.5;
    return c;
  }

  // A box (min, max corners) in the ground truth; written into the map on the next write().
  void add_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    boxes_.emplace_back(lo, hi);
    truth_.add_box(0.5 * (lo + hi), hi - lo);
    pending_.emplace_back(lo, hi);
  }

  // Writes the observed region (first call) or the boxes added since (later calls) as one
  // map update, and returns the snapshot.
  std::shared_ptr<const tsdf::MapSnapshot> write() {
    const uint64_t seq = map_.begin_update();
    if (!written_) {
      write_region(observed_, seq);
      written_ = true;
    } else {
      for (const Eigen::AlignedBox3d& b : pending_) {
        // the voxels a new box touches, clipped to the observed region
        const Eigen::AlignedBox3d grown(b.min() - Eigen::Vector3d::Constant(voxel_m_),
                                        b.max() + Eigen::Vector3d::Constant(voxel_m_));
        write_region(grown.intersection(observed_), seq);
      }
    }
    pending_.clear();
    return map_.snapshot();
  }

  const ObstacleGeometry& truth() const { return truth_; }
  double voxel_m() const { return voxel_m_; }

 private:
  bool touches_box(const tsdf::VoxelIndex& v) const {
    const Eigen::Vector3d lo = v.cast<double>() * voxel_m_;
    const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(voxel_m_);
    constexpr double kEps = 1e-9;
    for (const Eigen::AlignedBox3d& b : boxes_)
      if ((hi.array() > b.min().array() + kEps).all() &&
          (lo.array() < b.max().array() - kEps).all())
        return true;
    return false;
  }

  void write_region(const Eigen::AlignedBox3d& region, uint64_t seq) {
    if (region.isEmpty()) return;
    const auto v = static_cast<float>(voxel_m_);
    const Eigen::Vector3i lo =
        (region.min() / voxel_m_ + Eigen::Vector3d::Constant(1e-9)).array().floor().cast<int>();
    const Eigen::Vector3i hi =
        (region.max() / voxel_m_ - Eigen::Vector3d::Constant(1e-9)).array().floor().cast<int>();
    for (int z = lo.z(); z <= hi.z(); ++z)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int x = lo.x(); x <= hi.x(); ++x) {
          const tsdf::VoxelIndex i(x, y, z);
          tsdf::Block& block = map_.touch(tsdf::block_of(i));
          block.modified = seq;
          const Eigen::Vector3i l = tsdf::local_of(i);
          block.at(l.x(), l.y(), l.z()) =
              touches_box(i) ? tsdf::Voxel{-0.5f * v, 1.0f} : tsdf::Voxel{v, 1.0f};
        }
  }

  double voxel_m_;
  Eigen::AlignedBox3d observed_;
  tsdf::TsdfMap map_;
  std::vector<Eigen::AlignedBox3d> boxes_, pending_;
  ObstacleGeometry truth_;
  bool written_ = false;
};

}  // namespace scancrew::motion::test
