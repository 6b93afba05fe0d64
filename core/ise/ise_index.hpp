#pragma once

// ISE voxel → its index in the ISE list, stored by TSDF block: a block holding ISEs gets a
// table of its 512 voxels' ids. The visibility rays (gain.cpp) cross ~30 voxels each and
// look every voxel up; with one table per block a lookup is an array read once the ray's
// block is known, where a hash map of voxels cost a hash and a probe per voxel (the
// powerplant trio: 47 % of a run's CPU time in visibility, docs/ise_bench.md).

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/ise/ise.hpp"

namespace scancrew::ise {

class IseIndex {
 public:
  static constexpr uint32_t kNone = UINT32_MAX;
  using BlockIds = std::array<uint32_t, tsdf::kBlockVoxels>;

  void reserve(size_t ises);
  // Maps v to id; false (and nothing changes) when v already has an id or id is kNone.
  bool emplace(const VoxelIndex& v, uint32_t id);
  // v's id, kNone when v holds no ISE.
  uint32_t find(const VoxelIndex& v) const;
  // The ids of block b's voxels (slot() orders them), nullptr when b holds no ISE.
  const BlockIds* block(const BlockIndex& b) const;

  static BlockIndex block_of(const VoxelIndex& v) {
    static_assert(tsdf::kBlockSide == 8, "block_of and slot shift by 3");
    return {v.x() >> 3, v.y() >> 3, v.z() >> 3};  // floor, as tsdf::block_of
  }
  static int slot(const VoxelIndex& v) { return (v.x() & 7) | (v.y() & 7) << 3 | (v.z() & 7) << 6; }

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

 private:
  std::unordered_map<BlockIndex, uint32_t, tsdf::BlockIndexHash> blocks_;  // → tables_
  std::vector<BlockIds> tables_;
  size_t size_ = 0;
};

}  // namespace scancrew::ise
