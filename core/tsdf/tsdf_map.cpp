#include "core/tsdf/tsdf_map.hpp"

#include <cmath>
#include <limits>

namespace scancrew::tsdf {

std::string TsdfConfig::validate() const {
  if (!(voxel_m > 0.005 && voxel_m <= 10)) return "voxel_m must be in (0.005, 10]";
  if (!(truncation_m >= voxel_m && truncation_m <= 100 * voxel_m))
    return "truncation_m must be in [voxel_m, 100·voxel_m]";
  if (!(w_th > 0)) return "w_th must be > 0";
  if (!(max_weight >= w_th)) return "max_weight must be >= w_th";
  if (!(min_range_m >= 0 && max_range_m > min_range_m && max_range_m <= 1000))
    return "min_range_m and max_range_m must satisfy 0 <= min < max <= 1000";
  if (weight != TsdfWeight::kInverseSquare && weight != TsdfWeight::kConstant)
    return "weight must be inverse_square or constant";
  if (tile_px < 1 || tile_px > 64) return "tile_px must be in [1, 64]";
  if (clear_beyond_range && !(max_range_m > truncation_m))
    return "clear_beyond_range needs max_range_m > truncation_m (rays clear up to max − μ)";
  return {};
}

MapSnapshot::MapSnapshot(TsdfConfig config, uint64_t sequence, BlockTable<const Block> blocks)
    : config_(config), sequence_(sequence), blocks_(std::move(blocks)) {}

const Block* MapSnapshot::block(const BlockIndex& b) const {
  const auto it = blocks_.find(b);
  return it == blocks_.end() ? nullptr : it->second.get();
}

const Voxel* MapSnapshot::voxel(const VoxelIndex& v) const {
  const Block* b = block(block_of(v));
  if (b == nullptr) return nullptr;
  const Eigen::Vector3i l = local_of(v);
  return &b->at(l.x(), l.y(), l.z());
}

VoxelState MapSnapshot::state(const VoxelIndex& v) const {
  const Voxel* voxel = this->voxel(v);
  return voxel == nullptr ? VoxelState::kUnknown
                          : state_of(*voxel, static_cast<float>(config_.w_th));
}

std::optional<double> MapSnapshot::distance(const Eigen::Vector3d& p) const {
  const Voxel* v = voxel(voxel_of(p, voxel_m()));
  if (v == nullptr || !(v->weight >= config_.w_th)) return std::nullopt;
  return v->distance_m;
}

std::optional<MapSnapshot::RayResult> MapSnapshot::cast_ray(const Eigen::Vector3d& origin,
                                                            const Eigen::Vector3d& direction,
                                                            double max_m,
                                                            bool stop_at_unknown) const {
  const double norm = direction.norm();
  if (!(norm > 0) || !std::isfinite(norm) || !origin.allFinite()) return std::nullopt;
  const Eigen::Vector3d d = direction / norm;
  const double s = voxel_m();
  VoxelIndex v = voxel_of(origin, s);
  Eigen::Vector3i step;
  Eigen::Vector3d t_max, t_delta;
  for (int i = 0; i < 3; ++i) {
    if (d[i] > 0) {
      step[i] = 1;
      t_max[i] = ((v[i] + 1) * s - origin[i]) / d[i];
      t_delta[i] = s / d[i];
    } else if (d[i] < 0) {
      step[i] = -1;
      t_max[i] = (v[i] * s - origin[i]) / d[i];
      t_delta[i] = -s / d[i];
    } else {
      step[i] = 0;
      t_max[i] = std::numeric_limits<double>::infinity();
      t_delta[i] = std::numeric_limits<double>::infinity();
    }
  }
  double t = 0;
  while (t <= max_m) {
    const VoxelState st = state(v);
    if (st == VoxelState::kOccupied || (stop_at_unknown && st == VoxelState::kUnknown))
      return RayResult{{v, t}, st == VoxelState::kUnknown};
    int axis = 0;
    if (t_max[1] < t_max[axis]) axis = 1;
    if (t_max[2] < t_max[axis]) axis = 2;
    t = t_max[axis];
    t_max[axis] += t_delta[axis];
    v[axis] += step[axis];
  }
  return std::nullopt;
}

std::vector<BlockIndex> MapSnapshot::changed_since(uint64_t sequence) const {
  std::vector<BlockIndex> out;
  for (const auto& [index, block] : blocks_)
    if (block->modified > sequence) out.push_back(index);
  return out;
}

const Block* TsdfMap::find(const BlockIndex& b) const {
  const auto it = blocks_.find(b);
  return it == blocks_.end() ? nullptr : it->second.get();
}

Block* TsdfMap::find_mutable(const BlockIndex& b) {
  const auto it = blocks_.find(b);
  if (it == blocks_.end()) return nullptr;
  // shared with a snapshot: copy before writing (a snapshot released meanwhile only makes
  // the count smaller, so a count of 1 is always safe to write in place)
  if (it->second.use_count() > 1) it->second = std::make_shared<Block>(*it->second);
  return it->second.get();
}

Block& TsdfMap::touch(const BlockIndex& b) {
  auto [it, inserted] = blocks_.try_emplace(b);
  if (inserted)
    it->second = std::make_shared<Block>();
  else if (it->second.use_count() > 1)
    it->second = std::make_shared<Block>(*it->second);
  return *it->second;
}

std::shared_ptr<const MapSnapshot> TsdfMap::snapshot() const {
  BlockTable<const Block> table;
  table.reserve(blocks_.size());
  for (const auto& [index, block] : blocks_) table.emplace(index, block);
  return std::make_shared<const MapSnapshot>(config_, sequence_, std::move(table));
}

}  // namespace scancrew::tsdf
