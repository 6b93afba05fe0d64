#pragma once

// IsePipeline: from a map snapshot to the ISE set C, the remaining set C_rem, merged
// viewpoints, clusters and gains (thesis 2.4.2, 2.4.3, Definitions 1-4), incrementally.
//
// update() recomputes only what the blocks written (or removed) since the last snapshot can
// change:
//   ISEs: the changed blocks and their 26 neighbour blocks (an ISE reads its neighbours);
//   candidate viewpoints: those of the recomputed ISEs, and the feasibility of every cached
//     candidate whose clearance region meets a changed block;
//   visibility (C_q): viewpoints whose frustum box meets a recomputed block; the others
//     keep their cached C_q (a viewpoint is identified by its type and exact pose);
//   merging and clustering run over all viewpoints each time (linear, hashed).
// full() recomputes everything; update() and full() give the same result for the same
// snapshot (tested).
//
// C_ins and C_rem: an ISE is inspectable when some robot type has a feasible viewpoint of
// its own for it, or some feasible viewpoint sees it; the others form C_rem (reported, not
// planned for). An ISE given up (give_up(): the team stood at viewpoints that see it and it
// stayed incomplete, ise_extractor.hpp) is in C_rem too: no viewpoint is made for it, and
// viewpoints that saw only given-up ISEs are dropped (a deviation from the thesis, which has
// no such rule: docs/ise.md, "Visited and still incomplete"). Completion: no inspectable ISE over
// completion_updates consecutive updates, once the map has had ISEs (an empty map at the start is
// not a finished job).

#include <cstdint>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/ise/clusters.hpp"
#include "core/ise/gain.hpp"
#include "core/ise/ise.hpp"
#include "core/ise/ise_config.hpp"
#include "core/ise/viewpoints.hpp"
#include "core/result.hpp"

namespace scancrew::ise {

struct IseStats {
  bool full = false;
  size_t changed_blocks = 0;  // written since the last update
  size_t dirty_blocks = 0;    // ISEs recomputed in these (changed and their neighbours)
  size_t candidates = 0;      // feasible candidate viewpoints before merging
  size_t visibility_computed = 0, visibility_reused = 0;
  double extract_ms = 0, viewpoints_ms = 0, visibility_ms = 0, cluster_ms = 0, total_ms = 0;
};

struct IseResult {
  uint64_t map_sequence = 0;
  std::vector<Ise> ises;             // C, blocks in (z, y, x) order, voxels in block order
  std::vector<uint8_t> inspectable;  // per ISE: 1 in C_ins, 0 in C_rem
  std::vector<uint32_t> remaining;   // C_rem (indices into ises)
  size_t inspectable_count = 0;
  std::vector<Viewpoint> viewpoints;  // merged, feasible
  std::vector<Cluster> clusters;
  bool complete = false;  // C_ins empty over completion_updates consecutive updates
  IseStats stats;
};

struct BlockOrder {
  bool operator()(const BlockIndex& a, const BlockIndex& b) const {
    if (a.z() != b.z()) return a.z() < b.z();
    if (a.y() != b.y()) return a.y() < b.y();
    return a.x() < b.x();
  }
};

class IsePipeline {
 public:
  // Fails with every problem of the configuration (IseConfig::validate against the map's
  // W_th and voxel size).
  static Result<IsePipeline, std::string> create(const IseConfig& config, double w_th,
                                                 double voxel_m);

  const IseResult& update(const tsdf::MapSnapshot& snap);
  const IseResult& full(const tsdf::MapSnapshot& snap);
  const IseResult& result() const { return result_; }
  // From the next update on, these ISE voxels are in C_rem whatever viewpoints see them.
  void give_up(const std::vector<VoxelIndex>& voxels) {
    given_up_.insert(voxels.begin(), voxels.end());
  }
  size_t given_up_count() const { return given_up_.size(); }
  const IseConfig& config() const { return config_; }

 private:
  explicit IsePipeline(IseConfig config) : config_(std::move(config)) {}
  struct BlockCandidates {
    std::vector<Viewpoint> candidates;  // ises: the ISE's index within its block
    std::vector<uint8_t> feasible;
  };
  struct Seen {
    BlockIndex lo, hi;  // frustum box, blocks
    std::vector<VoxelIndex> ises;
  };
  struct PoseKey {
    int type;
    int64_t x, y, z, yaw;
    bool operator==(const PoseKey&) const = default;
  };
  struct PoseKeyHash {
    size_t operator()(const PoseKey& k) const;
  };

  void run(const tsdf::MapSnapshot& snap, const std::vector<BlockIndex>& changed, bool full);
  // run()'s steps (ise_pipeline.cpp)
  void extract_dirty(const tsdf::MapSnapshot& snap, const std::vector<BlockIndex>& dirty);
  void make_candidates(const std::vector<BlockIndex>& dirty);
  void check_feasibility(const tsdf::MapSnapshot& snap,
                         const std::unordered_set<BlockIndex, tsdf::BlockIndexHash>& near_changed,
                         bool full);
  std::vector<Viewpoint> gather(IseResult& out, IseIndex& index,
                                std::vector<uint8_t>& gave_up) const;
  void assign_types(const tsdf::MapSnapshot& snap, std::vector<Viewpoint>& viewpoints) const;
  size_t compute_visibility(const tsdf::MapSnapshot& snap, double block_m, const IseIndex& index,
                            IseResult& out);
  const RobotTypeSpec& spec(RobotKind type) const;
  static PoseKey key_of(const Viewpoint& v);

  IseConfig config_;
  bool have_ = false;
  uint64_t sequence_ = 0;
  double voxel_m_ = 0;
  bool had_ises_ = false;
  int empty_updates_ = 0;
  std::vector<BlockIndex> blocks_;  // the last snapshot's blocks, to notice removed ones
  StateGrid states_;                // the last snapshot's voxel states, compact
  std::map<BlockIndex, std::vector<Ise>, BlockOrder> ises_;
  std::map<BlockIndex, BlockCandidates, BlockOrder> candidates_;
  std::unordered_map<PoseKey, Seen, PoseKeyHash> seen_;
  std::unordered_set<VoxelIndex, tsdf::BlockIndexHash> given_up_;
  IseResult result_;
};

}  // namespace scancrew::ise
