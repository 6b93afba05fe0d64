#pragma once

// Incomplete Surface Elements (thesis 2.2 Definition 1, 2.4.2) and their view directions.
//
//   ISE: a voxel v with  a) w(v) ≥ W_th and φ(v) > 0                  (empty)
//                        b) some 6-neighbour u with w(u) < W_th        (unknown)
//                        c) some 18-neighbour o with w(o) ≥ W_th, φ(o) ≤ 0  (occupied)
//   A voxel never observed (no block) is unknown.
//   Scanned element (Definition 3): every 6-neighbour known.
//   View direction: n_v = Σ_{c ∈ N26(v)} w'(c)·(c − v)/|c − v|, w'(c) = −W_th when c is
//   occupied, +W_th otherwise; n̄_v = n_v/|n_v|: away from the occupied side. An ISE whose
//   sum vanishes has no direction (it gets no viewpoint of its own).
//
// Extraction runs per block (one padded 10³ grid of voxel states per block, so neighbours
// across block borders are read once); blocks are independent and run in parallel.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::ise {

using tsdf::BlockIndex;
using tsdf::VoxelIndex;

struct Ise {
  VoxelIndex voxel;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();     // voxel centre, world frame (m)
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // n̄_v; zero when undefined
  bool has_direction() const { return direction.squaredNorm() > 0; }
};

bool is_ise(const tsdf::MapSnapshot& snap, const VoxelIndex& v);
bool is_scanned(const tsdf::MapSnapshot& snap, const VoxelIndex& v);
// n̄_v, or nullopt where the weighted sum vanishes.
std::optional<Eigen::Vector3d> view_direction(const tsdf::MapSnapshot& snap, const VoxelIndex& v);

// The ISEs whose voxel lies in `block`, in voxel order (x fastest).
std::vector<Ise> extract_block(const tsdf::MapSnapshot& snap, const BlockIndex& block);

// The ISEs of the given blocks, in parallel; one vector per block, in the given order.
std::vector<std::vector<Ise>> extract_blocks(const tsdf::MapSnapshot& snap,
                                             const std::vector<BlockIndex>& blocks);

// Cached voxel reads along a path (ray casts, clearance checks): the last block is kept.
class VoxelReader {
 public:
  explicit VoxelReader(const tsdf::MapSnapshot& snap)
      : snap_(&snap), w_th_(static_cast<float>(snap.config().w_th)) {}
  const tsdf::Voxel* voxel(const VoxelIndex& v) {
    const BlockIndex b(v.x() >> 3, v.y() >> 3, v.z() >> 3);  // kBlockSide = 8, floor
    if (!have_ || b != last_index_) {
      last_ = snap_->block(b);
      last_index_ = b;
      have_ = true;
    }
    if (last_ == nullptr) return nullptr;
    return &last_->at(v.x() & 7, v.y() & 7, v.z() & 7);
  }
  tsdf::VoxelState state(const VoxelIndex& v) {
    const tsdf::Voxel* p = voxel(v);
    return p == nullptr ? tsdf::VoxelState::kUnknown : tsdf::state_of(*p, w_th_);
  }

 private:
  static_assert(tsdf::kBlockSide == 8, "VoxelReader shifts by 3");
  const tsdf::MapSnapshot* snap_;
  float w_th_;
  const tsdf::Block* last_ = nullptr;
  BlockIndex last_index_ = BlockIndex::Zero();
  bool have_ = false;
};

}  // namespace scancrew::ise
