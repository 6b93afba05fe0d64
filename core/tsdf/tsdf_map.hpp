#pragma once

// TsdfMap: the writable TSDF (blocks in a hash table) and MapSnapshot, its immutable,
// reference-counted copy. Blocks are shared between the map and its snapshots and copied
// on write (thesis architecture: "immutable snapshots, copy-on-write blocks"), so the
// ISE extractor and the planners read a consistent map while integration goes on, with
// no lock and no full copy: a snapshot costs one pointer per block.
//
// Thread safety: a TsdfMap is written by one thread at a time (the integrator parallelises
// inside one call). A MapSnapshot is immutable and may be read from any number of threads.

#include <Eigen/Geometry>
#include <algorithm>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "core/tsdf/block.hpp"
#include "core/tsdf/tsdf_config.hpp"

namespace scancrew::tsdf {

template <class B>
using BlockTable = std::unordered_map<BlockIndex, std::shared_ptr<B>, BlockIndexHash>;

struct RayHit {
  VoxelIndex voxel;       // the first occupied voxel along the ray
  double distance_m = 0;  // from the origin to where the ray enters it
};

class MapSnapshot {
 public:
  MapSnapshot(TsdfConfig config, uint64_t sequence, BlockTable<const Block> blocks);

  const TsdfConfig& config() const { return config_; }
  double voxel_m() const { return config_.voxel_m; }
  // The map's update sequence number when the snapshot was taken.
  uint64_t sequence() const { return sequence_; }
  const BlockTable<const Block>& blocks() const { return blocks_; }
  size_t block_count() const { return blocks_.size(); }

  // Null where the block was never observed.
  const Block* block(const BlockIndex& b) const;
  const Voxel* voxel(const VoxelIndex& v) const;
  VoxelState state(const VoxelIndex& v) const;
  VoxelState state_at(const Eigen::Vector3d& p) const { return state(voxel_of(p, voxel_m())); }
  // The voxel's signed distance (m) where it is known (w ≥ W_th).
  std::optional<double> distance(const Eigen::Vector3d& p) const;

  // The first occupied voxel along the ray within max_m (3D DDA, Amanatides & Woo 1987);
  // nullopt when the ray meets none. With stop_at_unknown, an unknown voxel ends the
  // ray too (reported as a hit with hit_unknown set).
  struct RayResult {
    RayHit hit;
    bool hit_unknown = false;
  };
  std::optional<RayResult> cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                    double max_m, bool stop_at_unknown = false) const;

  // Calls f(voxel index, voxel) for every occupied voxel.
  template <class F>
  void for_each_occupied(F&& f) const {
    const auto w_th = static_cast<float>(config_.w_th);
    for (const auto& [index, block] : blocks_)
      for (int z = 0; z < kBlockSide; ++z)
        for (int y = 0; y < kBlockSide; ++y)
          for (int x = 0; x < kBlockSide; ++x) {
            const Voxel& v = block->at(x, y, z);
            if (state_of(v, w_th) == VoxelState::kOccupied)
              f(VoxelIndex(index * kBlockSide + Eigen::Vector3i(x, y, z)), v);
          }
  }

  // Blocks written after the update with this sequence number (e.g. an earlier snapshot's
  // sequence()); blocks removed since are not listed.
  std::vector<BlockIndex> changed_since(uint64_t sequence) const;

 private:
  TsdfConfig config_;
  uint64_t sequence_ = 0;
  BlockTable<const Block> blocks_;
};

class TsdfMap {
 public:
  explicit TsdfMap(TsdfConfig config) : config_(config) {}

  const TsdfConfig& config() const { return config_; }
  uint64_t sequence() const { return sequence_; }
  // Starts an update: blocks written from now on carry the new sequence number.
  uint64_t begin_update() { return ++sequence_; }
  // Several maps that feed one snapshot (a robot's patches) share one sequence: before an
  // update, bring this map's counter up to the others'.
  void advance_sequence_to(uint64_t sequence) { sequence_ = std::max(sequence_, sequence); }

  const BlockTable<Block>& blocks() const { return blocks_; }
  size_t block_count() const { return blocks_.size(); }
  const Block* find(const BlockIndex& b) const;
  // The block, writable: allocated if absent, copied first if a snapshot shares it.
  Block& touch(const BlockIndex& b);
  // Like touch(), for an existing block only (null if absent).
  Block* find_mutable(const BlockIndex& b);
  void erase(const BlockIndex& b) { blocks_.erase(b); }
  void clear() { blocks_.clear(); }

  std::shared_ptr<const MapSnapshot> snapshot() const;

  // Voxel memory in bytes (blocks held by this map, shared ones included).
  size_t memory_bytes() const { return blocks_.size() * sizeof(Block); }

 private:
  TsdfConfig config_;
  uint64_t sequence_ = 0;
  BlockTable<Block> blocks_;
};

}  // namespace scancrew::tsdf
