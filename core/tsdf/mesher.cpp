#include "core/tsdf/mesher.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_set>

#include "core/tsdf/marching_cubes_tables.hpp"

namespace scancrew::tsdf {

namespace {

// The block's voxels and one voxel around them on the −x, −y, −z sides and two on the
// +x, +y, +z sides: the cubes' far corners (+1) and their central differences (−1, +2).
// Unobserved voxels are NaN.
constexpr int kGridSide = kBlockSide + 3;
constexpr int kGridVoxels = kGridSide * kGridSide * kGridSide;
using Grid = std::array<float, kGridVoxels>;

// Grid coordinate g holds block-local voxel g − 1.
constexpr int grid_index(int x, int y, int z) {
  return x + kGridSide * (y + kGridSide * z);
}

// One vertex per cut edge: the edge from block-local voxel (x, y, z), 0..kBlockSide, along
// axis a.
constexpr int kEdgeSide = kBlockSide + 1;
constexpr int kEdgeSlots = kEdgeSide * kEdgeSide * kEdgeSide * 3;
constexpr uint32_t kNoVertex = std::numeric_limits<uint32_t>::max();

void gather(const MapSnapshot& snap, const BlockIndex& index, float min_weight, Grid& grid) {
  grid.fill(std::numeric_limits<float>::quiet_NaN());
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        const Block* block = snap.block(index + Eigen::Vector3i(ox, oy, oz));
        if (block == nullptr) continue;
        // the neighbour's local range that falls into the grid: its last layer (−1), all
        // (0) or its first two layers (+1)
        auto lo = [](int o) { return o < 0 ? kBlockSide - 1 : 0; };
        auto hi = [](int o) { return o > 0 ? 2 : kBlockSide; };
        for (int z = lo(oz); z < hi(oz); ++z)
          for (int y = lo(oy); y < hi(oy); ++y)
            for (int x = lo(ox); x < hi(ox); ++x) {
              const Voxel& v = block->at(x, y, z);
              if (!(v.weight > 0 && v.weight >= min_weight)) continue;
              grid[static_cast<size_t>(grid_index(ox * kBlockSide + x + 1, oy * kBlockSide + y + 1,
                                                  oz * kBlockSide + z + 1))] = v.distance_m;
            }
      }
}

// d/dx_axis at grid point g in distance per voxel: central where both neighbours are
// observed, else one-sided (a cube corner always has its cube neighbours observed).
float derivative(const Grid& grid, const Eigen::Vector3i& g, int axis) {
  Eigen::Vector3i step = Eigen::Vector3i::Zero();
  step[axis] = 1;
  const Eigen::Vector3i p = g + step, m = g - step;
  const float plus = grid[static_cast<size_t>(grid_index(p.x(), p.y(), p.z()))];
  const float minus = grid[static_cast<size_t>(grid_index(m.x(), m.y(), m.z()))];
  const float centre = grid[static_cast<size_t>(grid_index(g.x(), g.y(), g.z()))];
  const bool has_plus = !std::isnan(plus), has_minus = !std::isnan(minus);
  if (has_plus && has_minus) return 0.5f * (plus - minus);
  if (has_plus) return plus - centre;
  if (has_minus) return centre - minus;
  return 0;
}

Eigen::Vector3f gradient(const Grid& grid, const Eigen::Vector3i& g) {
  return {derivative(grid, g, 0), derivative(grid, g, 1), derivative(grid, g, 2)};
}

// The lower corner of each cube edge and the axis it runs along.
struct EdgeGeometry {
  std::array<std::array<int, 3>, 12> low{};
  std::array<int, 12> axis{};
};

constexpr EdgeGeometry edge_geometry() {
  EdgeGeometry e;
  for (size_t j = 0; j < 12; ++j) {
    const auto& a = kMcCornerOffset[static_cast<size_t>(kMcEdgeCorners[j][0])];
    const auto& b = kMcCornerOffset[static_cast<size_t>(kMcEdgeCorners[j][1])];
    for (size_t i = 0; i < 3; ++i) {
      e.low[j][i] = std::min(a[i], b[i]);
      if (a[i] != b[i]) e.axis[j] = static_cast<int>(i);
    }
  }
  return e;
}
constexpr EdgeGeometry kEdges = edge_geometry();

bool index_less(const BlockIndex& a, const BlockIndex& b) {
  if (a.z() != b.z()) return a.z() < b.z();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.x() < b.x();
}

// adds the vertex where the surface cuts the edge from local voxel `low` along `axis`, with
// its gradient normal (zero, and needs_face_normals set, where the gradient vanishes);
// returns its index
uint32_t add_edge_vertex(const Grid& grid, const Eigen::Vector3i& origin,
                         const Eigen::Vector3i& low, int axis, double voxel_m, BlockMesh& mesh,
                         bool& needs_face_normals) {
  Eigen::Vector3i high = low;
  high[axis] += 1;
  const Eigen::Vector3i g0 = low + Eigen::Vector3i::Ones();
  const Eigen::Vector3i g1 = high + Eigen::Vector3i::Ones();
  const float d0 = grid[static_cast<size_t>(grid_index(g0.x(), g0.y(), g0.z()))];
  const float d1 = grid[static_cast<size_t>(grid_index(g1.x(), g1.y(), g1.z()))];
  // the signs differ, so d0 ≠ d1 and t ∈ [0, 1]
  const double t = static_cast<double>(d0) / (static_cast<double>(d0) - d1);
  Eigen::Vector3d p = (origin + low).cast<double>() + Eigen::Vector3d::Constant(0.5);
  p[axis] += t;
  const Eigen::Vector3f n =
      (1 - static_cast<float>(t)) * gradient(grid, g0) + static_cast<float>(t) * gradient(grid, g1);
  const float norm = n.norm();
  needs_face_normals |= !(norm > 1e-12f);
  const auto vertex = static_cast<uint32_t>(mesh.vertices.size());
  mesh.vertices.push_back((p * voxel_m).cast<float>());
  mesh.normals.push_back(norm > 1e-12f ? Eigen::Vector3f(n / norm) : Eigen::Vector3f::Zero());
  return vertex;
}

// where the gradient vanished: the area-weighted normal of the vertex's triangles
void fill_face_normals(BlockMesh& mesh) {
  std::vector<Eigen::Vector3f> sum(mesh.vertices.size(), Eigen::Vector3f::Zero());
  for (const Triangle& t : mesh.triangles) {
    const Eigen::Vector3f n = (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                                  .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    for (uint32_t i : t) sum[i] += n;
  }
  for (size_t i = 0; i < mesh.normals.size(); ++i)
    if (mesh.normals[i].isZero(0)) {
      const float norm = sum[i].norm();
      mesh.normals[i] = norm > 0 ? Eigen::Vector3f(sum[i] / norm) : Eigen::Vector3f::UnitZ();
    }
}

}  // namespace

BlockMesh mesh_block(const MapSnapshot& snap, const BlockIndex& index, float min_weight) {
  BlockMesh mesh;
  const Block* block = snap.block(index);
  if (block == nullptr) return mesh;
  mesh.owner = block->owner;

  Grid grid;
  gather(snap, index, min_weight, grid);
  std::array<uint32_t, kEdgeSlots> edge_vertex;
  edge_vertex.fill(kNoVertex);
  const McTables& tables = mc_tables();
  const double voxel_m = snap.voxel_m();
  const Eigen::Vector3i origin = index * kBlockSide;  // global index of local voxel 0
  bool needs_face_normals = false;

  for (int z = 0; z < kBlockSide; ++z)
    for (int y = 0; y < kBlockSide; ++y)
      for (int x = 0; x < kBlockSide; ++x) {
        // the cube's corner distances; skip it unless all 8 are observed
        std::array<float, 8> d{};
        int config = 0;
        bool observed = true;
        for (size_t i = 0; i < 8 && observed; ++i) {
          const auto& o = kMcCornerOffset[i];
          d[i] = grid[static_cast<size_t>(grid_index(x + 1 + o[0], y + 1 + o[1], z + 1 + o[2]))];
          observed = !std::isnan(d[i]);
          if (d[i] < 0) config |= 1 << i;
        }
        if (!observed) continue;
        const uint16_t cut = tables.edges[static_cast<size_t>(config)];
        if (cut == 0) continue;

        // a vertex on each cut edge, shared with the block's other cubes on that edge
        std::array<uint32_t, 12> vertex{};
        for (size_t j = 0; j < 12; ++j) {
          if ((cut & (1u << j)) == 0) continue;
          const auto& o = kEdges.low[j];
          const Eigen::Vector3i low(x + o[0], y + o[1], z + o[2]);
          const int axis = kEdges.axis[j];
          const int slot_index = ((low.z() * kEdgeSide + low.y()) * kEdgeSide + low.x()) * 3 + axis;
          const auto slot = static_cast<size_t>(slot_index);
          if (edge_vertex[slot] == kNoVertex)
            edge_vertex[slot] =
                add_edge_vertex(grid, origin, low, axis, voxel_m, mesh, needs_face_normals);
          vertex[j] = edge_vertex[slot];
        }

        // the table's triangles face inside: reverse them
        const auto& tri = tables.triangles[static_cast<size_t>(config)];
        for (size_t k = 0; k < 15 && tri[k] >= 0; k += 3)
          mesh.triangles.push_back({vertex[static_cast<uint8_t>(tri[k])],
                                    vertex[static_cast<uint8_t>(tri[k + 2])],
                                    vertex[static_cast<uint8_t>(tri[k + 1])]});
      }

  if (needs_face_normals) fill_face_normals(mesh);
  return mesh;
}

void Mesher::clear() {
  blocks_.clear();
  stats_ = {};
  sequence_ = 0;
  meshed_ = false;
}

void Mesher::remesh(const MapSnapshot& snap, std::vector<BlockIndex> indices) {
  const auto w = static_cast<float>(config_.min_weight);
  std::vector<BlockMesh> meshes(indices.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, indices.size()),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i)
                        meshes[i] = mesh_block(snap, indices[i], w);
                    });
  stats_.meshed_blocks = indices.size();
  stats_.triangles = 0;
  for (size_t i = 0; i < indices.size(); ++i) {
    stats_.triangles += meshes[i].triangles.size();
    blocks_[indices[i]] = std::move(meshes[i]);
  }
  sequence_ = snap.sequence();
  voxel_m_ = snap.voxel_m();
  meshed_ = true;
}

MeshStats Mesher::full(const MapSnapshot& snap) {
  const auto start = std::chrono::steady_clock::now();
  blocks_.clear();
  stats_ = {};
  stats_.full = true;
  std::vector<BlockIndex> all;
  all.reserve(snap.block_count());
  for (const auto& [index, block] : snap.blocks()) all.push_back(index);
  stats_.changed_blocks = all.size();
  remesh(snap, std::move(all));
  stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats_;
}

MeshStats Mesher::update(const MapSnapshot& snap) {
  if (!meshed_ || snap.sequence() < sequence_ || snap.voxel_m() != voxel_m_) return full(snap);
  const auto start = std::chrono::steady_clock::now();
  stats_ = {};

  // the changed and removed blocks, then every block within one block of them
  const std::vector<BlockIndex> changed = snap.changed_since(sequence_);
  std::vector<BlockIndex> removed;
  for (const auto& [index, mesh] : blocks_)
    if (snap.block(index) == nullptr) removed.push_back(index);
  for (const BlockIndex& b : removed) blocks_.erase(b);
  stats_.changed_blocks = changed.size();
  stats_.removed_blocks = removed.size();

  std::unordered_set<BlockIndex, BlockIndexHash> dirty;
  auto mark_neighbourhood = [&](const BlockIndex& b) {
    for (int z = -1; z <= 1; ++z)
      for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
          const BlockIndex n = b + Eigen::Vector3i(x, y, z);
          if (snap.block(n) != nullptr) dirty.insert(n);
        }
  };
  for (const BlockIndex& b : changed) mark_neighbourhood(b);
  for (const BlockIndex& b : removed) mark_neighbourhood(b);

  remesh(snap, std::vector<BlockIndex>(dirty.begin(), dirty.end()));
  stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats_;
}

Mesh Mesher::assemble(Weld weld) const {
  std::vector<const std::pair<const BlockIndex, BlockMesh>*> order;
  order.reserve(blocks_.size());
  size_t vertex_count = 0, triangle_count = 0;
  for (const auto& entry : blocks_) {
    if (entry.second.triangles.empty()) continue;
    order.push_back(&entry);
    vertex_count += entry.second.vertices.size();
    triangle_count += entry.second.triangles.size();
  }
  std::sort(order.begin(), order.end(),
            [](const auto* a, const auto* b) { return index_less(a->first, b->first); });

  Mesh mesh;
  mesh.vertices.reserve(vertex_count);
  mesh.normals.reserve(vertex_count);
  mesh.owners.reserve(vertex_count);
  mesh.triangles.reserve(triangle_count);

  // across blocks, vertices on a shared edge have bit-identical positions (the same two
  // voxels, the same arithmetic): merge by position, keeping the first block's
  struct PositionHash {
    size_t operator()(const std::array<uint32_t, 3>& p) const {
      return static_cast<size_t>(p[0]) * 73856093u ^ static_cast<size_t>(p[1]) * 19349669u ^
             static_cast<size_t>(p[2]) * 83492791u;
    }
  };
  std::unordered_map<std::array<uint32_t, 3>, uint32_t, PositionHash> merged;
  std::vector<uint32_t> remap;
  for (const auto* entry : order) {
    const BlockMesh& b = entry->second;
    remap.resize(b.vertices.size());
    for (size_t i = 0; i < b.vertices.size(); ++i) {
      const auto next = static_cast<uint32_t>(mesh.vertices.size());
      if (weld == Weld::kAcrossBlocks) {
        std::array<uint32_t, 3> key{};
        std::memcpy(key.data(), b.vertices[i].data(), sizeof(key));
        const auto [it, inserted] = merged.try_emplace(key, next);
        remap[i] = it->second;
        if (!inserted) continue;
      } else {
        remap[i] = next;
      }
      mesh.vertices.push_back(b.vertices[i]);
      mesh.normals.push_back(b.normals[i]);
      mesh.owners.push_back(b.owner);
    }
    for (const Triangle& t : b.triangles) {
      const Triangle r = {remap[t[0]], remap[t[1]], remap[t[2]]};
      if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;  // collapsed by merging
      mesh.triangles.push_back(r);
    }
  }
  return mesh;
}

}  // namespace scancrew::tsdf
