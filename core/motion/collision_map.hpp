#pragma once

// CollisionMap: the map's obstacles as an OctoMap octree (Hornung et al. 2013) wrapped in
// an FCL octree (Pan et al. 2012), and the robot body tested against it — the state
// validity of the low-level planner (thesis 2.5.3, LazyPRM* in the TSDF's free space).
//
// The octree's resolution is the TSDF voxel and its leaves are voxels (key = voxel index +
// 2^15 per axis, as tsdf/octomap_export.hpp). It holds the occupied voxels of the snapshot
// (φ ≤ 0, w ≥ W_th) and, with unknown_is_occupied, the unknown voxels of observed blocks;
// free voxels are absent, or free leaves where an obstacle voxel became free. Blocks never observed
// are not put in the tree: with unknown_is_occupied, a body that overlaps one (FCL, body against
// the block's box) collides.
//
// update() is incremental: a snapshot shares unchanged blocks with the previous one by
// pointer (copy on write, tsdf_map.hpp), and this class holds the previous snapshot, so a
// block whose pointer differs (or that appeared or vanished) is exactly a block whose
// content may have changed; only its 512 voxels are rewritten. A snapshot with another
// voxel size rebuilds the tree.
//
// Not thread safe: one thread updates and queries (the planner's).

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "core/robot/body_model.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::motion {

struct CollisionMapUpdate {
  std::vector<tsdf::BlockIndex> changed;  // rewritten, added or removed blocks
  size_t removed_blocks = 0;
  bool rebuilt = false;     // the whole tree was (re)built (first map, new voxel size)
  size_t out_of_range = 0;  // voxels outside OctoMap's key range, skipped
  double ms = 0;
};

class CollisionMap {
 public:
  CollisionMap(const robot::BodyModel& body, bool unknown_is_occupied);
  ~CollisionMap();
  CollisionMap(CollisionMap&&) noexcept;
  CollisionMap& operator=(CollisionMap&&) noexcept;

  // Brings the octree to `snapshot` (non-null). Keeps a reference to it.
  CollisionMapUpdate update(std::shared_ptr<const tsdf::MapSnapshot> snapshot);

  // Whether the body at T_world_body overlaps an obstacle (false before the first map:
  // no map, no obstacle — callers check has_map()).
  bool collides(const Eigen::Isometry3d& T_world_body) const;

  bool has_map() const;
  const std::shared_ptr<const tsdf::MapSnapshot>& snapshot() const;
  // The observed blocks' box (empty without a map).
  Eigen::AlignedBox3d extents() const;
  // The state of the voxel holding p: kUnknown outside the observed blocks too.
  tsdf::VoxelState state_at(const Eigen::Vector3d& p) const;
  const robot::BodyModel& body() const;
  bool unknown_is_occupied() const;
  size_t leaf_count() const;  // leaves of the (pruned) tree, free ones included
  size_t checks() const;      // collides() calls so far

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::motion
