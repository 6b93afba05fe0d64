#pragma once

// Fusion of patches into a map (thesis 4.4.1): the global estimate of a robot is its
// private and public patches fused voxel by voxel, weights summed and distances
// weight-averaged. Only the patch's blocks are touched, so fusing is incremental.

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "core/tsdf/patch_codec.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::tsdf {

struct FuseStats {
  size_t blocks = 0;      // blocks of the map written
  size_t new_blocks = 0;  // of those, absent before
  size_t voxels = 0;      // voxels written (w > 0 in the source)
};

// Fusion of a source block into a map block (thesis 4.4.1), per voxel with w_s > 0:
//   w = w_d + w_s,  φ = (φ_d·w_d + φ_s·w_s) / w,  w ← min(w, max_weight),
// so fusing patches equals integrating their depth maps into one map while no weight
// saturates (the weighted mean is associative). The block's owner becomes source_owner
// when the source's total weight exceeds the block's. Returns the voxels written.
size_t fuse_block(Block& dst, const Block& src, float max_weight, uint32_t source_owner);

// One voxel of fuse_block (s.weight > 0).
inline void fuse_voxel(Voxel& d, const Voxel& s, float max_weight) {
  const double w = static_cast<double>(d.weight) + s.weight;
  d.distance_m = static_cast<float>((static_cast<double>(d.distance_m) * d.weight +
                                     static_cast<double>(s.distance_m) * s.weight) /
                                    w);
  d.weight = std::min(static_cast<float>(w), max_weight);
}

// Fuses a decoded patch into the map as one update (map.begin_update()): only the patch's
// blocks are written (copied first when a snapshot shares them), their modified set to the
// new sequence number.
FuseStats fuse_blocks(TsdfMap& map, const DecodedPatch& patch);

// The same for the blocks of another map or snapshot (e.g. a robot's own, not encoded),
// contributed by robot owner. Source blocks without an observed voxel are skipped. The
// source must not be map's own table.
template <class B>
FuseStats fuse_map(TsdfMap& dst, const BlockTable<B>& src, uint32_t owner) {
  FuseStats stats;
  const uint64_t sequence = dst.begin_update();
  const auto max_weight = static_cast<float>(dst.config().max_weight);
  for (const auto& [index, block] : src) {
    bool observed = false;
    for (const Voxel& v : block->voxels) observed = observed || v.weight > 0;
    if (!observed) continue;
    stats.new_blocks += dst.find(index) == nullptr ? 1 : 0;
    Block& b = dst.touch(index);
    stats.voxels += fuse_block(b, *block, max_weight, owner);
    b.modified = sequence;
    ++stats.blocks;
  }
  return stats;
}

}  // namespace scancrew::tsdf
