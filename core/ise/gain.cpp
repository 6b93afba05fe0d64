#include "core/ise/gain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scancrew::ise {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Walks the voxels along origin + t·dir for t in [t0, t1] (Amanatides & Woo); f(voxel)
// returns false to stop.
template <class F>
void walk(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t0, double t1, double r,
          F&& f) {
  const Eigen::Vector3d start = origin + t0 * dir;
  tsdf::VoxelIndex v = tsdf::voxel_of(start, r);
  Eigen::Vector3i step;
  Eigen::Vector3d t_max, t_delta;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] > 0) {
      step[a] = 1;
      t_max[a] = ((v[a] + 1) * r - start[a]) / dir[a];
      t_delta[a] = r / dir[a];
    } else if (dir[a] < 0) {
      step[a] = -1;
      t_max[a] = (v[a] * r - start[a]) / dir[a];
      t_delta[a] = -r / dir[a];
    } else {
      step[a] = 0;
      t_max[a] = std::numeric_limits<double>::infinity();
      t_delta[a] = std::numeric_limits<double>::infinity();
    }
  }
  const double length = t1 - t0;
  double t = 0;
  while (t <= length) {
    if (!f(v)) return;
    int a = 0;
    if (t_max[1] < t_max[a]) a = 1;
    if (t_max[2] < t_max[a]) a = 2;
    t = t_max[a];
    t_max[a] += t_delta[a];
    v[a] += step[a];
  }
}

// visible_ises() on either reader: the TSDF's voxels (VoxelReader) or their compact states
// (StateGrid::Reader); both give the same states, so the same result.
template <class Reader>
std::vector<uint32_t> visible_with(Reader reader, double r, const IseIndex& ises,
                                   const RobotTypeSpec& type, int rows, int cols,
                                   const Eigen::Vector3d& position, double yaw_rad) {
  std::vector<uint32_t> seen;
  if (ises.empty()) return seen;
  const double th = std::tan(0.5 * type.fov_h_deg * kDegToRad);
  const double tv = std::tan(0.5 * type.fov_v_deg * kDegToRad);
  const Eigen::Vector3d forward(std::cos(yaw_rad), std::sin(yaw_rad), 0);
  const Eigen::Vector3d left(-std::sin(yaw_rad), std::cos(yaw_rad), 0);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  BlockIndex ids_of = IseIndex::block_of(tsdf::voxel_of(position, r));
  const IseIndex::BlockIds* ids = ises.block(ids_of);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      // ray through the centre of cell (i, j) of a rows × cols grid over the image plane
      const double x = th * (2.0 * (j + 0.5) / cols - 1.0);
      const double y = tv * (1.0 - 2.0 * (i + 0.5) / rows);
      const Eigen::Vector3d d = (forward - x * left + y * up).normalized();
      // the range is along the optical axis, as depth: t·(d·forward)
      const double cos_axis = d.dot(forward);
      walk(position, d, type.min_range_m / cos_axis, type.max_range_m / cos_axis, r,
           [&](const tsdf::VoxelIndex& v) {
             const tsdf::VoxelState s = reader.state(v);
             if (s == tsdf::VoxelState::kOccupied) return false;
             if (s == tsdf::VoxelState::kUnknown && !type.viewpoint_in_unknown) return false;
             // the ISE table of v's block, looked up again only when the ray leaves it
             const BlockIndex b = IseIndex::block_of(v);
             if (b != ids_of) {
               ids = ises.block(b);
               ids_of = b;
             }
             if (ids != nullptr) {
               const uint32_t id = (*ids)[static_cast<size_t>(IseIndex::slot(v))];
               if (id != IseIndex::kNone) seen.push_back(id);
             }
             return true;
           });
    }
  std::sort(seen.begin(), seen.end());
  seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
  return seen;
}

}  // namespace

std::vector<uint32_t> visible_ises(const tsdf::MapSnapshot& snap, const IseIndex& ises,
                                   const RobotTypeSpec& type, int rows, int cols,
                                   const Eigen::Vector3d& position, double yaw_rad) {
  return visible_with(VoxelReader(snap), snap.voxel_m(), ises, type, rows, cols, position, yaw_rad);
}

std::vector<uint32_t> visible_ises(const StateGrid& states, double voxel_m, const IseIndex& ises,
                                   const RobotTypeSpec& type, int rows, int cols,
                                   const Eigen::Vector3d& position, double yaw_rad) {
  return visible_with(StateGrid::Reader(states), voxel_m, ises, type, rows, cols, position,
                      yaw_rad);
}

void view_bounds(const RobotTypeSpec& type, const Eigen::Vector3d& position, double yaw_rad,
                 double block_m, BlockIndex& lo, BlockIndex& hi) {
  // the frustum is the convex hull of the camera and the far plane's four corners
  const double th = std::tan(0.5 * type.fov_h_deg * kDegToRad);
  const double tv = std::tan(0.5 * type.fov_v_deg * kDegToRad);
  const Eigen::Vector3d forward(std::cos(yaw_rad), std::sin(yaw_rad), 0);
  const Eigen::Vector3d left(-std::sin(yaw_rad), std::cos(yaw_rad), 0);
  Eigen::Vector3d a = position, b = position;
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0}) {
      const Eigen::Vector3d corner =
          position +
          type.max_range_m * (forward + sx * th * left + sy * tv * Eigen::Vector3d::UnitZ());
      a = a.cwiseMin(corner);
      b = b.cwiseMax(corner);
    }
  for (int i = 0; i < 3; ++i) {
    // one voxel of margin: the DDA may step into the voxel beyond the hull's face
    lo[i] = static_cast<int>(std::floor((a[i] - block_m / tsdf::kBlockSide) / block_m));
    hi[i] = static_cast<int>(std::floor((b[i] + block_m / tsdf::kBlockSide) / block_m));
  }
}

}  // namespace scancrew::ise
