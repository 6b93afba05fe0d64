#include "core/ise/viewpoints.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace scancrew::ise {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

const RobotTypeSpec* spec_of(const IseConfig& config, RobotKind type) {
  for (const RobotTypeSpec& t : config.robot_types)
    if (t.type == type) return &t;
  return nullptr;
}

}  // namespace

std::optional<Viewpoint> candidate(const Ise& ise, const RobotTypeSpec& type) {
  if (!ise.has_direction()) return std::nullopt;
  const Eigen::Vector3d n = ise.direction;
  const double half_v = 0.5 * type.fov_v_deg * kDegToRad;
  Viewpoint vp;
  vp.type = type.type;
  if (type.type == RobotKind::kGround) {
    const Eigen::Vector2d h(n.x(), n.y());
    if (h.norm() < 1e-6) return std::nullopt;
    const Eigen::Vector2d u = h.normalized();
    const double z = type.floor_z_m + type.camera_height_m;
    vp.position = Eigen::Vector3d(ise.center.x() + type.delta_pose_m * u.x(),
                                  ise.center.y() + type.delta_pose_m * u.y(), z);
    // elevation of the ISE seen from the camera
    if (std::abs(std::atan2(ise.center.z() - z, type.delta_pose_m)) > half_v) return std::nullopt;
  } else {
    const double max_elevation = 0.8 * half_v;
    Eigen::Vector3d d = n;
    const double horizontal = std::hypot(d.x(), d.y());
    const double elevation = std::atan2(d.z(), horizontal);
    if (std::abs(elevation) > max_elevation) {
      // keep the azimuth (any one where n̄ is vertical), clamp the elevation
      const double azimuth = horizontal > 1e-9 ? std::atan2(d.y(), d.x()) : 0.0;
      const double e = std::copysign(max_elevation, elevation);
      d = Eigen::Vector3d(std::cos(e) * std::cos(azimuth), std::cos(e) * std::sin(azimuth),
                          std::sin(e));
    }
    vp.position = ise.center + type.delta_pose_m * d;
    // into the altitude band, if the ISE stays in view from there
    const double z = std::clamp(vp.position.z(), type.min_altitude_m, type.max_altitude_m);
    if (z != vp.position.z()) {
      vp.position.z() = z;
      const double flat = (ise.center - vp.position).head<2>().norm();
      if (std::abs(std::atan2(ise.center.z() - z, flat)) > half_v) return std::nullopt;
    }
  }
  const Eigen::Vector3d look = ise.center - vp.position;
  vp.yaw_rad = std::atan2(look.y(), look.x());
  return vp;
}

namespace {

// feasible() on either reader (VoxelReader or StateGrid::Reader: the same states).
template <class Reader>
bool feasible_with(Reader reader, double r, const RobotTypeSpec& type,
                   const Eigen::Vector3d& position) {
  const int reach = static_cast<int>(std::ceil(type.clearance_m / r));
  const tsdf::VoxelIndex c = tsdf::voxel_of(position, r);
  const tsdf::VoxelState own = reader.state(c);
  if (own != tsdf::VoxelState::kEmpty &&
      !(type.viewpoint_in_unknown && own == tsdf::VoxelState::kUnknown))
    return false;
  auto free = [&](const tsdf::VoxelIndex& v) {
    const tsdf::VoxelState s = reader.state(v);
    return s == tsdf::VoxelState::kEmpty ||
           (type.unknown_is_free && s == tsdf::VoxelState::kUnknown);
  };
  const double r2 = (type.clearance_m + 0.5 * r) * (type.clearance_m + 0.5 * r);
  if (type.type == RobotKind::kGround) {
    const int z0 = static_cast<int>(std::floor(type.floor_z_m / r)) + 1;
    const int z1 = static_cast<int>(std::floor((type.floor_z_m + type.body_height_m) / r));
    // the floor under the robot is known: occupied within a voxel of floor_z, or seen at a
    // grazing angle: the voxel holding the floor's surface unknown (a hit farther than a
    // few metres updates no voxel behind the surface, so the floor voxel is never
    // integrated) under known empty air. A doorway's far room was glimpsed so and its floor
    // stayed unknown; no viewpoint there was feasible, its ISEs all went to C_rem and an
    // indoor pair met the criterion with 68 % of the reachable surface (Step 11,
    // indoor_5). A known empty floor voxel is a hole
    bool floor = false;
    for (int z = z0 - 2; z <= z0 && !floor; ++z)
      floor = reader.state({c.x(), c.y(), z}) == tsdf::VoxelState::kOccupied;
    if (!floor) {
      const int zf = static_cast<int>(std::floor((type.floor_z_m - 0.5 * r) / r));
      floor = reader.state({c.x(), c.y(), zf}) == tsdf::VoxelState::kUnknown &&
              reader.state({c.x(), c.y(), zf + 1}) == tsdf::VoxelState::kEmpty;
    }
    if (!floor) return false;
    for (int z = z0; z <= std::max(z0, z1); ++z)
      for (int y = -reach; y <= reach; ++y)
        for (int x = -reach; x <= reach; ++x) {
          if ((x * x + y * y) * r * r > r2) continue;
          if (!free({c.x() + x, c.y() + y, z})) return false;
        }
    return true;
  }
  for (int z = -reach; z <= reach; ++z)
    for (int y = -reach; y <= reach; ++y)
      for (int x = -reach; x <= reach; ++x) {
        if ((x * x + y * y + z * z) * r * r > r2) continue;
        if (!free(c + tsdf::VoxelIndex(x, y, z))) return false;
      }
  return true;
}

}  // namespace

bool feasible(const tsdf::MapSnapshot& snap, const RobotTypeSpec& type,
              const Eigen::Vector3d& position) {
  return feasible_with(VoxelReader(snap), snap.voxel_m(), type, position);
}

bool feasible(const StateGrid& states, double voxel_m, const RobotTypeSpec& type,
              const Eigen::Vector3d& position) {
  return feasible_with(StateGrid::Reader(states), voxel_m, type, position);
}

std::vector<Viewpoint> merge(const tsdf::MapSnapshot& snap, const IseConfig& config,
                             std::vector<Viewpoint> candidates) {
  const double eps = config.merge_distance_m;
  const double min_cos = std::cos(config.merge_angle_deg * kDegToRad);
  std::vector<Viewpoint> out;
  if (eps <= 0) return candidates;
  // merged viewpoints by (type, ε-cell) of their first member's position
  struct Key {
    int type, x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return static_cast<size_t>(k.x) * 73856093u ^ static_cast<size_t>(k.y) * 19349669u ^
             static_cast<size_t>(k.z) * 83492791u ^ static_cast<size_t>(k.type);
    }
  };
  std::unordered_map<Key, std::vector<size_t>, KeyHash> cells;
  std::vector<Eigen::Vector3d> sums;  // per merged viewpoint: position and look sums
  std::vector<Eigen::Vector3d> look_sums;
  std::vector<int> counts;
  auto key_of = [&](RobotKind t, const Eigen::Vector3d& p) {
    return Key{static_cast<int>(t), static_cast<int>(std::floor(p.x() / eps)),
               static_cast<int>(std::floor(p.y() / eps)),
               static_cast<int>(std::floor(p.z() / eps))};
  };
  for (Viewpoint& c : candidates) {
    const Key k = key_of(c.type, c.position);
    const Eigen::Vector3d look = c.look();
    size_t best = out.size();
    double best_d = eps;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells.find({k.type, k.x + dx, k.y + dy, k.z + dz});
          if (it == cells.end()) continue;
          for (size_t m : it->second) {
            const double d = (out[m].position - c.position).norm();
            if (d < best_d && out[m].look().dot(look) >= min_cos) {
              best_d = d;
              best = m;
            }
          }
        }
    if (best < out.size()) {
      const Eigen::Vector3d sum = sums[best] + c.position;
      const Eigen::Vector3d look_sum = look_sums[best] + look;
      const int n = counts[best] + 1;
      const Eigen::Vector3d position = sum / n;
      const RobotTypeSpec* spec = spec_of(config, c.type);
      if (look_sum.head<2>().norm() > 1e-9 && spec != nullptr && feasible(snap, *spec, position)) {
        Viewpoint& m = out[best];
        m.position = position;
        m.yaw_rad = std::atan2(look_sum.y(), look_sum.x());
        m.ises.insert(m.ises.end(), c.ises.begin(), c.ises.end());
        sums[best] = sum;
        look_sums[best] = look_sum;
        counts[best] = n;
        continue;
      }
    }
    cells[k].push_back(out.size());
    sums.push_back(c.position);
    look_sums.push_back(look);
    counts.push_back(1);
    out.push_back(std::move(c));
  }
  for (Viewpoint& v : out) std::sort(v.ises.begin(), v.ises.end());
  return out;
}

}  // namespace scancrew::ise
