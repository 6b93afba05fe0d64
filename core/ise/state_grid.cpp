#include "core/ise/state_grid.hpp"

namespace scancrew::ise {

void StateGrid::rebuild(const tsdf::MapSnapshot& snap) {
  w_th_ = static_cast<float>(snap.config().w_th);
  blocks_.clear();
  blocks_.reserve(snap.block_count());
  for (const auto& [index, block] : snap.blocks()) set(index, *block);
}

void StateGrid::refresh(const tsdf::MapSnapshot& snap,
                        const std::vector<tsdf::BlockIndex>& blocks) {
  w_th_ = static_cast<float>(snap.config().w_th);
  for (const tsdf::BlockIndex& b : blocks) {
    if (const tsdf::Block* block = snap.block(b))
      set(b, *block);
    else
      blocks_.erase(b);
  }
}

void StateGrid::set(const tsdf::BlockIndex& index, const tsdf::Block& block) {
  BlockStates& s = blocks_[index];
  for (size_t i = 0; i < s.size(); ++i) {
    uint8_t packed = 0;
    for (size_t k = 0; k < 4; ++k)
      packed |= static_cast<uint8_t>(
          static_cast<uint8_t>(tsdf::state_of(block.voxels[4 * i + k], w_th_)) << (2 * k));
    s[i] = packed;
  }
}

}  // namespace scancrew::ise
