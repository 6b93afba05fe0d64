#pragma once

// Hand-made voxel maps for the ISE tests: voxels written one by one or as boxes, in a chosen
// state, with each written block stamped with the current update's sequence number (as the
// integrator does), so IsePipeline::update() sees exactly the blocks a test changed.
//
// occupied = {distance −0.05 m, weight 1}, empty = {distance +0.1 m, weight 1}, unknown =
// weight 0 (or a voxel never written: no block). W_th is 0.5, voxels are 0.1 m.

#include <array>
#include <memory>
#include <set>
#include <vector>

#include "core/ise/ise.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::ise::test {

using tsdf::VoxelState;

inline constexpr double kVoxelM = 0.1;
inline constexpr double kWth = 0.5;

inline tsdf::TsdfConfig scene_config() {
  tsdf::TsdfConfig c;
  c.voxel_m = kVoxelM;
  c.truncation_m = 3 * kVoxelM;
  c.w_th = kWth;
  return c;
}

inline tsdf::Voxel voxel_in(VoxelState s) {
  switch (s) {
    case VoxelState::kOccupied:
      return {-0.05f, 1.0f};
    case VoxelState::kEmpty:
      return {0.1f, 1.0f};
    case VoxelState::kUnknown:
      break;
  }
  return {0.0f, 0.0f};
}

class VoxelScene {
 public:
  VoxelScene() : map_(scene_config()) { sequence_ = map_.begin_update(); }

  // Starts a new map update: blocks written from now on are "changed since" the last one.
  void next_update() { sequence_ = map_.begin_update(); }

  void set_voxel(const VoxelIndex& v, const tsdf::Voxel& value) {
    tsdf::Block& block = map_.touch(tsdf::block_of(v));
    block.modified = sequence_;
    const Eigen::Vector3i l = tsdf::local_of(v);
    block.at(l.x(), l.y(), l.z()) = value;
  }
  void set(const VoxelIndex& v, VoxelState s) { set_voxel(v, voxel_in(s)); }
  // Every voxel of the box [lo, hi] (inclusive).
  void fill(const VoxelIndex& lo, const VoxelIndex& hi, VoxelState s) {
    for (int z = lo.z(); z <= hi.z(); ++z)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int x = lo.x(); x <= hi.x(); ++x) set({x, y, z}, s);
  }
  // Removes a whole block (the voxels it held become unknown).
  void erase_block(const BlockIndex& b) { map_.erase(b); }

  std::shared_ptr<const tsdf::MapSnapshot> snapshot() const { return map_.snapshot(); }
  std::vector<BlockIndex> blocks() const {
    std::vector<BlockIndex> out;
    for (const auto& [index, block] : map_.blocks()) out.push_back(index);
    return out;
  }

 private:
  tsdf::TsdfMap map_;
  uint64_t sequence_ = 0;
};

// Voxel indices as comparable keys, for set equality in assertions.
using Key = std::array<int, 3>;
inline Key key(const VoxelIndex& v) {
  return {v.x(), v.y(), v.z()};
}

inline std::set<Key> voxels_of(const std::vector<Ise>& ises) {
  std::set<Key> out;
  for (const Ise& ise : ises) out.insert(key(ise.voxel));
  return out;
}

// Every ISE of the snapshot, by extracting all its blocks.
inline std::vector<Ise> extract_all(const tsdf::MapSnapshot& snap) {
  std::vector<BlockIndex> blocks;
  for (const auto& [index, block] : snap.blocks()) blocks.push_back(index);
  std::vector<Ise> out;
  for (const std::vector<Ise>& list : extract_blocks(snap, blocks))
    out.insert(out.end(), list.begin(), list.end());
  return out;
}

}  // namespace scancrew::ise::test
