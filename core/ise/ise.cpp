#include "core/ise/ise.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cstdlib>

namespace scancrew::ise {

using tsdf::kBlockSide;
using tsdf::VoxelState;

namespace {

// A block's voxel states with a one-voxel border from its neighbours.
constexpr int kPad = kBlockSide + 2;
using StateGrid = std::array<VoxelState, static_cast<size_t>(kPad* kPad* kPad)>;
constexpr int grid_index(int x, int y, int z) {
  return x + kPad * (y + kPad * z);
}

void gather(const tsdf::MapSnapshot& snap, const BlockIndex& index, StateGrid& grid) {
  grid.fill(VoxelState::kUnknown);
  const auto w_th = static_cast<float>(snap.config().w_th);
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        const tsdf::Block* block = snap.block(index + Eigen::Vector3i(ox, oy, oz));
        if (block == nullptr) continue;
        auto lo = [](int o) { return o < 0 ? kBlockSide - 1 : 0; };
        auto hi = [](int o) { return o > 0 ? 1 : kBlockSide; };
        for (int z = lo(oz); z < hi(oz); ++z)
          for (int y = lo(oy); y < hi(oy); ++y)
            for (int x = lo(ox); x < hi(ox); ++x)
              grid[static_cast<size_t>(grid_index(ox * kBlockSide + x + 1, oy * kBlockSide + y + 1,
                                                  oz * kBlockSide + z + 1))] =
                  tsdf::state_of(block->at(x, y, z), w_th);
      }
}

struct Offset {
  int x, y, z;
  int order;  // |x| + |y| + |z|: 1 face (6), 2 edge (18 with faces), 3 corner (26)
};
constexpr std::array<Offset, 26> kNeighbours = [] {
  std::array<Offset, 26> out{};
  size_t i = 0;
  for (int z = -1; z <= 1; ++z)
    for (int y = -1; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x)
        if (x != 0 || y != 0 || z != 0)
          out[i++] = {x, y, z, (x != 0 ? 1 : 0) + (y != 0 ? 1 : 0) + (z != 0 ? 1 : 0)};
  return out;
}();

template <class StateAt>
bool ise_at(StateAt&& state_at) {
  if (state_at(0, 0, 0) != VoxelState::kEmpty) return false;
  bool unknown = false, occupied = false;
  for (const Offset& o : kNeighbours) {
    if (o.order == 1 && !unknown) unknown = state_at(o.x, o.y, o.z) == VoxelState::kUnknown;
    if (o.order <= 2 && !occupied) occupied = state_at(o.x, o.y, o.z) == VoxelState::kOccupied;
  }
  return unknown && occupied;
}

template <class StateAt>
std::optional<Eigen::Vector3d> direction_at(StateAt&& state_at, double w_th) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (const Offset& o : kNeighbours) {
    const double w = state_at(o.x, o.y, o.z) == VoxelState::kOccupied ? -w_th : w_th;
    n += w * Eigen::Vector3d(o.x, o.y, o.z).normalized();
  }
  // exact cancellations leave rounding residue: a sum below 1e-9·W_th is zero
  if (n.norm() <= 1e-9 * w_th) return std::nullopt;
  return n.normalized();
}

}  // namespace

bool is_ise(const tsdf::MapSnapshot& snap, const VoxelIndex& v) {
  VoxelReader reader(snap);
  return ise_at([&](int x, int y, int z) { return reader.state(v + Eigen::Vector3i(x, y, z)); });
}

bool is_scanned(const tsdf::MapSnapshot& snap, const VoxelIndex& v) {
  VoxelReader reader(snap);
  for (const Offset& o : kNeighbours)
    if (o.order == 1 && reader.state(v + Eigen::Vector3i(o.x, o.y, o.z)) == VoxelState::kUnknown)
      return false;
  return true;
}

std::optional<Eigen::Vector3d> view_direction(const tsdf::MapSnapshot& snap, const VoxelIndex& v) {
  VoxelReader reader(snap);
  return direction_at(
      [&](int x, int y, int z) { return reader.state(v + Eigen::Vector3i(x, y, z)); },
      snap.config().w_th);
}

std::vector<Ise> extract_block(const tsdf::MapSnapshot& snap, const BlockIndex& block) {
  std::vector<Ise> out;
  if (snap.block(block) == nullptr) return out;  // all unknown: no empty voxel
  StateGrid grid;
  gather(snap, block, grid);
  const double r = snap.voxel_m();
  for (int z = 1; z <= kBlockSide; ++z)
    for (int y = 1; y <= kBlockSide; ++y)
      for (int x = 1; x <= kBlockSide; ++x) {
        auto state_at = [&](int dx, int dy, int dz) {
          return grid[static_cast<size_t>(grid_index(x + dx, y + dy, z + dz))];
        };
        if (!ise_at(state_at)) continue;
        Ise ise;
        ise.voxel = block * kBlockSide + Eigen::Vector3i(x - 1, y - 1, z - 1);
        ise.center = tsdf::voxel_center(ise.voxel, r);
        if (auto n = direction_at(state_at, snap.config().w_th)) ise.direction = *n;
        out.push_back(ise);
      }
  return out;
}

std::vector<std::vector<Ise>> extract_blocks(const tsdf::MapSnapshot& snap,
                                             const std::vector<BlockIndex>& blocks) {
  std::vector<std::vector<Ise>> out(blocks.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.size(), 8),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i != range.end(); ++i)
                        out[i] = extract_block(snap, blocks[i]);
                    });
  return out;
}

}  // namespace scancrew::ise
