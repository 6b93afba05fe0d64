#include "core/motion/guide_path.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>

namespace scancrew::motion {

namespace {

enum Cell : uint8_t { kFree = 0, kBlocked = 1, kUnknown = 2 };

}  // namespace

GuideGrid::GuideGrid(const tsdf::MapSnapshot& map, const Eigen::AlignedBox2d& bounds,
                     const GuideConfig& config)
    : config_(config), bounds_(bounds), map_sequence_(map.sequence()), voxel_m_(map.voxel_m()) {
  if (bounds.isEmpty() || voxel_m_ <= 0) return;
  const Eigen::Vector2i lo = (bounds.min() / voxel_m_).array().floor().cast<int>();
  const Eigen::Vector2i hi = (bounds.max() / voxel_m_).array().floor().cast<int>();
  origin_ = lo;
  nx_ = hi.x() - lo.x() + 1;
  ny_ = hi.y() - lo.y() + 1;
  const int z_lo = static_cast<int>(std::floor(config.z_lo_m / voxel_m_));
  const int z_hi = static_cast<int>(std::floor(config.z_hi_m / voxel_m_));
  const int slab = z_hi - z_lo + 1;

  // per cell: an occupied voxel in the slab, and how many of its voxels are known free
  std::vector<uint8_t> occupied(static_cast<size_t>(nx_) * static_cast<size_t>(ny_), 0);
  std::vector<uint16_t> free_count(occupied.size(), 0);
  const auto w_th = static_cast<float>(map.config().w_th);
  for (const auto& [index, block] : map.blocks()) {
    const int bz0 = index.z() * tsdf::kBlockSide;
    const int vz0 = std::max(z_lo, bz0), vz1 = std::min(z_hi, bz0 + tsdf::kBlockSide - 1);
    if (vz0 > vz1) continue;
    for (int y = 0; y < tsdf::kBlockSide; ++y) {
      const int cy = index.y() * tsdf::kBlockSide + y - origin_.y();
      if (cy < 0 || cy >= ny_) continue;
      for (int x = 0; x < tsdf::kBlockSide; ++x) {
        const int cx = index.x() * tsdf::kBlockSide + x - origin_.x();
        if (cx < 0 || cx >= nx_) continue;
        const size_t c =
            static_cast<size_t>(cy) * static_cast<size_t>(nx_) + static_cast<size_t>(cx);
        for (int vz = vz0; vz <= vz1; ++vz) {
          const tsdf::VoxelState s = tsdf::state_of(block->at(x, y, vz - bz0), w_th);
          if (s == tsdf::VoxelState::kOccupied) occupied[c] = 1;
          if (s == tsdf::VoxelState::kEmpty) ++free_count[c];
        }
      }
    }
  }
  std::vector<uint8_t> blocked(occupied.size(), 0);
  for (size_t c = 0; c < blocked.size(); ++c)
    blocked[c] = occupied[c] != 0 ||
                 (config.unknown_is_occupied && free_count[c] < static_cast<uint16_t>(slab));

  // passable: some point of the cell may have the clearance, i.e. no blocked cell lies
  // within the clearance less half the cell's diagonal of its centre (a disc of cells)
  const double r_cells = std::max(config.clearance_m / voxel_m_ - 0.5 * std::sqrt(2.0), 0.0);
  const int r = static_cast<int>(std::ceil(r_cells));
  std::vector<Eigen::Vector2i> disc;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      // a blocked cell counts when its nearest point is within the clearance
      if (std::hypot(std::max(std::abs(dx) - 0.5, 0.0), std::max(std::abs(dy) - 0.5, 0.0)) <
          r_cells)
        disc.emplace_back(dx, dy);
  passable_.assign(blocked.size(), 1);
  for (int cy = 0; cy < ny_; ++cy)
    for (int cx = 0; cx < nx_; ++cx) {
      if (blocked[static_cast<size_t>(cy) * static_cast<size_t>(nx_) + static_cast<size_t>(cx)] ==
          0)
        continue;
      for (const Eigen::Vector2i& d : disc) {
        const int x = cx + d.x(), y = cy + d.y();
        if (x >= 0 && x < nx_ && y >= 0 && y < ny_)
          passable_[static_cast<size_t>(y) * static_cast<size_t>(nx_) + static_cast<size_t>(x)] = 0;
      }
    }
}

bool GuideGrid::cell_of(const Eigen::Vector2d& p, Eigen::Vector2i& c) const {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return false;
  c = (p / voxel_m_).array().floor().cast<int>().matrix() - origin_;
  return c.x() >= 0 && c.x() < nx_ && c.y() >= 0 && c.y() < ny_;
}

std::vector<GuidePose> GuideGrid::search(const Eigen::Vector2d& start,
                                         const Eigen::Vector2d& goal) const {
  Eigen::Vector2i s, g;
  if (passable_.empty() || !cell_of(start, s) || !cell_of(goal, g)) return {};
  const auto id = [this](int x, int y) {
    return static_cast<size_t>(y) * static_cast<size_t>(nx_) + static_cast<size_t>(x);
  };
  const size_t s_id = id(s.x(), s.y()), g_id = id(g.x(), g.y());
  const auto octile = [&g](int x, int y) {
    const double dx = std::abs(x - g.x()), dy = std::abs(y - g.y());
    return std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy);
  };
  std::vector<float> cost(passable_.size(), std::numeric_limits<float>::infinity());
  std::vector<uint32_t> parent(passable_.size(), std::numeric_limits<uint32_t>::max());
  using Entry = std::pair<double, uint32_t>;  // f, cell
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  cost[s_id] = 0;
  open.emplace(octile(s.x(), s.y()), static_cast<uint32_t>(s_id));
  static constexpr std::array<std::array<int, 2>, 8> kSteps{
      {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}}};
  bool found = false;
  while (!open.empty()) {
    const auto [f, c] = open.top();
    open.pop();
    if (c == g_id) {
      found = true;
      break;
    }
    const int cx = static_cast<int>(c % static_cast<uint32_t>(nx_));
    const int cy = static_cast<int>(c / static_cast<uint32_t>(nx_));
    if (f > cost[c] + octile(cx, cy) + 1e-6) continue;  // a stale entry
    for (const auto& [dx, dy] : kSteps) {
      const int x = cx + dx, y = cy + dy;
      if (x < 0 || x >= nx_ || y < 0 || y >= ny_) continue;
      const size_t n = id(x, y);
      if (passable_[n] == 0 && n != g_id) continue;
      const float step = (dx != 0 && dy != 0) ? static_cast<float>(std::sqrt(2.0)) : 1.0F;
      if (cost[c] + step < cost[n]) {
        cost[n] = cost[c] + step;
        parent[n] = c;
        open.emplace(cost[n] + octile(x, y), static_cast<uint32_t>(n));
      }
    }
  }
  if (!found) return {};

  std::vector<Eigen::Vector2d> cells;  // goal to start
  for (uint32_t c = static_cast<uint32_t>(g_id); c != std::numeric_limits<uint32_t>::max();
       c = parent[c]) {
    const Eigen::Vector2i xy(static_cast<int>(c % static_cast<uint32_t>(nx_)),
                             static_cast<int>(c / static_cast<uint32_t>(nx_)));
    cells.push_back((xy + origin_).cast<double>().array() * voxel_m_ + 0.5 * voxel_m_);
    if (c == s_id) break;
  }
  std::reverse(cells.begin(), cells.end());
  // poses every spacing_m of arc length, the yaw along the path around them
  std::vector<GuidePose> poses;
  const double spacing = std::max(config_.spacing_m, voxel_m_);
  const auto half = static_cast<size_t>(std::max(1.0, std::round(0.5 * spacing / voxel_m_)));
  double arc = 0;
  for (size_t i = 1; i + 1 < cells.size(); ++i) {
    arc += (cells[i] - cells[i - 1]).norm();
    if (arc < spacing) continue;
    arc = 0;
    const Eigen::Vector2d d =
        cells[std::min(i + half, cells.size() - 1)] - cells[i - std::min(i, half)];
    poses.push_back({cells[i].x(), cells[i].y(), std::atan2(d.y(), d.x())});
  }
  return poses;
}

}  // namespace scancrew::motion
