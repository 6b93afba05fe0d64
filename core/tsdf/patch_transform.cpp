#include "core/tsdf/patch_transform.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace scancrew::tsdf {

namespace {

struct IndexLess {
  bool operator()(const BlockIndex& a, const BlockIndex& b) const {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  }
};

// The source patch's voxels by global index (observed: w > 0).
class Source {
 public:
  explicit Source(const DecodedPatch& patch) {
    for (const DecodedBlock& b : patch.blocks) blocks_.emplace(b.index, &b.block);
  }
  const Voxel* observed(const VoxelIndex& g) const {
    const auto it = blocks_.find(block_of(g));
    if (it == blocks_.end()) return nullptr;
    const Eigen::Vector3i l = local_of(g);
    const Voxel& v = it->second->at(l.x(), l.y(), l.z());
    return v.weight > 0 ? &v : nullptr;
  }

 private:
  std::unordered_map<BlockIndex, const Block*, BlockIndexHash> blocks_;
};

// Distance and weight at p, trilinear over the 8 voxel centres around it; false where one
// is unobserved.
bool resample(const Source& source, const Eigen::Vector3d& p, double voxel_m, Voxel& out) {
  const Eigen::Vector3d u = p / voxel_m - Eigen::Vector3d::Constant(0.5);
  const Eigen::Vector3d floor_u = u.array().floor();
  const Eigen::Vector3i base = floor_u.cast<int>();
  const Eigen::Vector3d f = u - floor_u;
  double distance = 0, weight = 0;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3i d(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const double w = (d.x() == 1 ? f.x() : 1 - f.x()) * (d.y() == 1 ? f.y() : 1 - f.y()) *
                     (d.z() == 1 ? f.z() : 1 - f.z());
    if (w < 1e-9) continue;  // a corner that does not count need not be observed
    const Voxel* v = source.observed(base + d);
    if (v == nullptr) return false;
    distance += w * v->distance_m;
    weight += w * v->weight;
  }
  out.distance_m = static_cast<float>(distance);
  out.weight = static_cast<float>(weight);
  return out.weight > 0;
}

}  // namespace

DecodedPatch transform_patch(const DecodedPatch& patch, double voxel_m,
                             const Eigen::Isometry3d& T) {
  const Source source(patch);
  const double block_m = voxel_m * kBlockSide;
  // the destination blocks: those the moved source blocks' boxes meet
  std::map<BlockIndex, bool, IndexLess> targets;  // in a fixed order
  for (const DecodedBlock& b : patch.blocks) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3i d(c & 1, (c >> 1) & 1, (c >> 2) & 1);
      const Eigen::Vector3d corner = T * ((b.index + d).cast<double>() * block_m);
      lo = lo.cwiseMin(corner);
      hi = hi.cwiseMax(corner);
    }
    const BlockIndex b_lo = block_of(voxel_of(lo, voxel_m)), b_hi = block_of(voxel_of(hi, voxel_m));
    for (int z = b_lo.z(); z <= b_hi.z(); ++z)
      for (int y = b_lo.y(); y <= b_hi.y(); ++y)
        for (int x = b_lo.x(); x <= b_hi.x(); ++x) targets.emplace(BlockIndex(x, y, z), true);
  }
  DecodedPatch out;
  out.patch_id = patch.patch_id;
  out.robot_id = patch.robot_id;
  out.index = patch.index;
  out.T_world_patch = patch.T_world_patch;
  const Eigen::Isometry3d inverse = T.inverse();
  for (const auto& [index, unused] : targets) {
    DecodedBlock block{.index = index, .block = {}};
    block.block.owner = patch.robot_id;
    size_t written = 0;
    for (int z = 0; z < kBlockSide; ++z)
      for (int y = 0; y < kBlockSide; ++y)
        for (int x = 0; x < kBlockSide; ++x) {
          const VoxelIndex g = index * kBlockSide + Eigen::Vector3i(x, y, z);
          if (resample(source, inverse * voxel_center(g, voxel_m), voxel_m,
                       block.block.at(x, y, z)))
            ++written;
        }
    if (written == 0) continue;
    out.observed_voxels += written;
    out.blocks.push_back(std::move(block));
  }
  return out;
}

}  // namespace scancrew::tsdf
