#pragma once

// The map's voxel states (unknown / empty / occupied, eq. 1.1 with W_th), two bits a voxel:
// the compact copy of a snapshot that the visibility rays and the clearance checks read.
//
// A block of the TSDF is 4 KiB (distance and weight, 8 bytes a voxel); its states are
// 128 bytes. Ray casting is bound by memory traffic, not arithmetic: a ray through a block
// touches a new cache line at almost every step. On the 2-bit copy a whole block is two
// cache lines, and the map of a 60 m site fits the L2 cache.
//
// IsePipeline keeps one StateGrid across its updates and refreshes only the blocks written
// since (MapSnapshot::changed_since), so the copy costs O(changed blocks) per update.

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::ise {

class StateGrid {
 public:
  using BlockStates = std::array<uint8_t, tsdf::kBlockVoxels / 4>;

  StateGrid() = default;
  // Every block of the snapshot.
  explicit StateGrid(const tsdf::MapSnapshot& snap) { rebuild(snap); }

  void rebuild(const tsdf::MapSnapshot& snap);
  // Refreshes the given blocks from the snapshot; one the snapshot lacks is dropped.
  void refresh(const tsdf::MapSnapshot& snap, const std::vector<tsdf::BlockIndex>& blocks);

  // Null where the block was never observed (all unknown).
  const BlockStates* block(const tsdf::BlockIndex& b) const {
    const auto it = blocks_.find(b);
    return it == blocks_.end() ? nullptr : &it->second;
  }
  size_t block_count() const { return blocks_.size(); }

  static tsdf::VoxelState state_in(const BlockStates& s, int local_index) {
    return static_cast<tsdf::VoxelState>(
        (s[static_cast<size_t>(local_index >> 2)] >> ((local_index & 3) * 2)) & 3u);
  }

  // Reads along a path (ray casts, clearance checks), keeping the last block: the same
  // interface as VoxelReader (ise.hpp), on the compact states.
  class Reader {
   public:
    explicit Reader(const StateGrid& grid) : grid_(&grid) {}
    tsdf::VoxelState state(const tsdf::VoxelIndex& v) {
      static_assert(tsdf::kBlockSide == 8, "Reader shifts by 3");
      const tsdf::BlockIndex b(v.x() >> 3, v.y() >> 3, v.z() >> 3);  // floor
      if (!have_ || b != last_index_) {
        last_ = grid_->block(b);
        last_index_ = b;
        have_ = true;
      }
      if (last_ == nullptr) return tsdf::VoxelState::kUnknown;
      return state_in(*last_, tsdf::Block::index(v.x() & 7, v.y() & 7, v.z() & 7));
    }

   private:
    const StateGrid* grid_;
    const BlockStates* last_ = nullptr;
    tsdf::BlockIndex last_index_ = tsdf::BlockIndex::Zero();
    bool have_ = false;
  };

 private:
  void set(const tsdf::BlockIndex& index, const tsdf::Block& block);

  float w_th_ = 0;
  std::unordered_map<tsdf::BlockIndex, BlockStates, tsdf::BlockIndexHash> blocks_;
};

}  // namespace scancrew::ise
