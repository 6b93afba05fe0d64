#include "core/tsdf/patch_fusion.hpp"

namespace scancrew::tsdf {

size_t fuse_block(Block& dst, const Block& src, float max_weight, uint32_t source_owner) {
  double dst_total = 0, src_total = 0;
  size_t written = 0;
  for (size_t i = 0; i < size_t{kBlockVoxels}; ++i) {
    Voxel& d = dst.voxels[i];
    const Voxel& s = src.voxels[i];
    dst_total += d.weight;
    if (!(s.weight > 0)) continue;
    src_total += s.weight;
    fuse_voxel(d, s, max_weight);
    ++written;
  }
  if (src_total > dst_total) dst.owner = source_owner;
  return written;
}

FuseStats fuse_blocks(TsdfMap& map, const DecodedPatch& patch) {
  FuseStats stats;
  const uint64_t sequence = map.begin_update();
  const auto max_weight = static_cast<float>(map.config().max_weight);
  for (const DecodedBlock& db : patch.blocks) {
    stats.new_blocks += map.find(db.index) == nullptr ? 1 : 0;
    Block& b = map.touch(db.index);
    stats.voxels += fuse_block(b, db.block, max_weight, db.block.owner);
    b.modified = sequence;
    ++stats.blocks;
  }
  return stats;
}

}  // namespace scancrew::tsdf
