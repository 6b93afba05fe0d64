#pragma once

// Mesher: the TSDF's zero level set as a triangle mesh, by marching cubes (Lorensen & Cline
// 1987; thesis 1.3.3, Fig. 4.7), kept up to date block by block.
//
// Cubes: a cube joins 8 neighbouring voxel centres; the cube whose min corner is voxel v
// belongs to v's block, so a block owns 8³ cubes and reads the voxels of its +x, +y, +z
// neighbours (and their diagonals) for the far corners. A cube is meshed only when all 8
// corners are observed (weight > 0 and ≥ min_weight), so no surface is made up at the border of
// the unknown. Vertices lie on the cube edges where the linearly interpolated distance is
// zero; a block's vertices are welded (one vertex per cut edge), vertices on edges shared
// with a neighbour block are repeated there (assemble() can weld them).
//
// Normals: the TSDF gradient by central differences at the edge's two voxels (one-sided
// where a neighbour is unobserved), interpolated along the edge; the mean normal of the
// vertex's triangles where the gradient vanishes. They point to positive distance
// (outside, into the observed free space); triangles are wound counter-clockwise seen
// from outside.
//
// Incremental: a block's mesh depends on the voxels of its 3×3×3 block neighbourhood
// (cube corners reach +1 voxel, the gradient −1 and +2), so update() remeshes every block
// within one block of a block changed since the last update (snapshot sequence numbers,
// MapSnapshot::changed_since) or removed from the map, and drops the meshes of removed
// blocks. The result equals full() on the same snapshot.
//
// Thread safety: a Mesher is used from one thread at a time; update() and full() read the
// snapshot from all cores (TBB, one task per block). The snapshot is not kept.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::tsdf {

using Triangle = std::array<uint32_t, 3>;  // vertex indices, counter-clockwise from outside

// One block's share of the mesh; positions in the world frame (m).
struct BlockMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3f> normals;  // unit, outward
  std::vector<Triangle> triangles;       // indices into this block's vertices
  uint32_t owner = 0;                    // the block's owner (robot id)
};

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3f> normals;
  std::vector<uint32_t> owners;  // per vertex: the owner of the block that made it
  std::vector<Triangle> triangles;
};

struct MesherConfig {
  // A cube corner counts as observed when its weight is positive and at least this. The
  // default 0 meshes every observed voxel, as the thesis's MarchingCubes over the whole TSDF
  // volume does (2.6.1, after Zeng et al. 2017); W_th (the known/unknown split, eq. 1.1)
  // decides the ISEs and the planners' free space, not the mesh. Set it to W_th to mesh
  // known voxels only.
  double min_weight = 0;
};

struct MeshStats {
  bool full = false;          // the whole map was remeshed
  size_t changed_blocks = 0;  // written since the last update (or new to the mesher)
  size_t removed_blocks = 0;  // gone from the map since the last update
  size_t meshed_blocks = 0;   // remeshed: the changed ones and their neighbours
  size_t triangles = 0;       // in the remeshed blocks
  double seconds = 0;         // wall time of the call
};

enum class Weld : uint8_t {
  kWithinBlocks,  // vertices on block faces repeated in each block (the cache as it is)
  kAcrossBlocks,  // also merged between blocks (exactly equal positions): a closed surface
                  // gives a closed mesh
};

// Meshes one block of the snapshot (its 8³ cubes) with the given observed threshold: the
// kernel behind Mesher, usable on its own. Allocates the result only.
BlockMesh mesh_block(const MapSnapshot& snap, const BlockIndex& index, float min_weight);

class Mesher {
 public:
  explicit Mesher(MesherConfig config = {}) : config_(config) {}

  // Remeshes what changed since the last update() or full(); the first call, a snapshot
  // older than the last one (a reset map) or a different voxel size remeshes all.
  MeshStats update(const MapSnapshot& snap);
  // Remeshes every block.
  MeshStats full(const MapSnapshot& snap);

  // The cached meshes as one mesh, blocks in index order (z, y, x), so the output is the
  // same for the same map whichever order blocks were meshed in. Allocates the result.
  Mesh assemble(Weld weld = Weld::kWithinBlocks) const;

  // Every block of the last snapshot has an entry (empty where it has no surface).
  const std::unordered_map<BlockIndex, BlockMesh, BlockIndexHash>& blocks() const {
    return blocks_;
  }
  const MeshStats& last_stats() const { return stats_; }
  // The sequence of the snapshot last meshed.
  uint64_t sequence() const { return sequence_; }
  void clear();

 private:
  void remesh(const MapSnapshot& snap, std::vector<BlockIndex> indices);

  MesherConfig config_;
  std::unordered_map<BlockIndex, BlockMesh, BlockIndexHash> blocks_;
  MeshStats stats_;
  uint64_t sequence_ = 0;
  double voxel_m_ = 0;
  bool meshed_ = false;
};

}  // namespace scancrew::tsdf
