#include "core/motion/obstacle_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/robot/body_model.hpp"

namespace scancrew::motion {

ObstacleCheckConfig ObstacleCheckConfig::for_kind(RobotKind kind) {
  ObstacleCheckConfig c;
  c.kind = kind;
  // the safety volume's sizes are the body's (one body model, core/robot/body_model.hpp)
  const robot::BodyModel body = robot::BodyModel::of(kind);
  c.sphere_radius_m = body.bounding_radius_m();
  c.semi_major_m = body.safety_radii_m.x();
  c.semi_minor_m = body.safety_radii_m.y();
  return c;
}

std::string ObstacleCheckConfig::validate() const {
  std::string e;
  auto add = [&e](const std::string& m) { e += (e.empty() ? "" : "; ") + m; };
  if (kind == RobotKind::kMultirotor) {
    if (!(sphere_radius_m > 0)) add("sphere_radius_m must be > 0");
  } else {
    if (!(semi_minor_m > 0)) add("semi_minor_m must be > 0");
    if (!(semi_major_m >= semi_minor_m)) add("semi_major_m must be >= semi_minor_m");
    if (!(max_height_m > min_height_m)) add("max_height_m must be > min_height_m");
  }
  if (max_voxels == 0) add("max_voxels must be > 0");
  return e;
}

const char* to_string(ObstacleStatus status) {
  switch (status) {
    case ObstacleStatus::kClear:
      return "clear";
    case ObstacleStatus::kObstacle:
      return "obstacle";
    case ObstacleStatus::kBadInput:
      return "bad_input";
  }
  return "?";
}

namespace {

// voxel index range [lo, hi] whose centres (i + 0.5)·h may lie within [a, b] (a margin of
// one voxel each side; the exact test in the loop decides)
void index_range(double a, double b, double h, long& lo, long& hi) {
  lo = static_cast<long>(std::floor(a / h - 0.5));
  hi = static_cast<long>(std::ceil(b / h - 0.5));
}

}  // namespace

ObstacleCheckResult obstacle_check(const Eigen::Vector3d& position, double yaw_rad, double voxel_m,
                                   const OccupancyQuery& occupied,
                                   const ObstacleCheckConfig& config) {
  ObstacleCheckResult r;
  const bool ground = config.kind == RobotKind::kGround;
  if (!position.allFinite() || !std::isfinite(yaw_rad) || !(voxel_m > 0) || !occupied ||
      !config.validate().empty()) {
    r.status = ObstacleStatus::kBadInput;
    return r;
  }
  // the volume grown by half a voxel
  const double h = voxel_m;
  const double grow = 0.5 * h;
  const double a = (ground ? config.semi_major_m : config.sphere_radius_m) + grow;
  const double b = (ground ? config.semi_minor_m : config.sphere_radius_m) + grow;
  const double z_lo = ground ? position.z() + config.min_height_m : position.z() - a;
  const double z_hi = ground ? position.z() + config.max_height_m : position.z() + a;
  // voxel indices must fit a long with room to spare
  const double reach = position.cwiseAbs().maxCoeff() + std::max(a, std::abs(z_hi - z_lo));
  if (!(reach / h < 1e15)) {
    r.status = ObstacleStatus::kBadInput;
    return r;
  }

  long x0 = 0, x1 = 0, y0 = 0, y1 = 0, z0 = 0, z1 = 0;
  index_range(position.x() - a, position.x() + a, h, x0, x1);
  index_range(position.y() - a, position.y() + a, h, y0, y1);
  index_range(z_lo, z_hi, h, z0, z1);
  const double count = static_cast<double>(x1 - x0 + 1) * static_cast<double>(y1 - y0 + 1) *
                       static_cast<double>(z1 - z0 + 1);
  if (!(count <= static_cast<double>(config.max_voxels))) {
    r.status = ObstacleStatus::kBadInput;
    return r;
  }

  const Eigen::Vector2d forward(std::cos(yaw_rad), std::sin(yaw_rad));
  const Eigen::Vector2d left(-forward.y(), forward.x());
  double best = std::numeric_limits<double>::infinity();  // normalised radius² of the deepest
  for (long iz = z0; iz <= z1; ++iz) {
    const double cz = (static_cast<double>(iz) + 0.5) * h;
    if (cz < z_lo || cz > z_hi) continue;
    for (long iy = y0; iy <= y1; ++iy) {
      const double cy = (static_cast<double>(iy) + 0.5) * h;
      for (long ix = x0; ix <= x1; ++ix) {
        const double cx = (static_cast<double>(ix) + 0.5) * h;
        const Eigen::Vector3d c(cx, cy, cz);
        const Eigen::Vector3d d = c - position;
        double rho2 = 0;
        if (ground) {
          const double u = forward.dot(d.head<2>()) / a;
          const double v = left.dot(d.head<2>()) / b;
          rho2 = u * u + v * v;
        } else {
          rho2 = d.squaredNorm() / (a * a);
        }
        if (rho2 > 1.0) continue;
        ++r.voxels_checked;
        if (rho2 >= best || !occupied(c)) continue;
        best = rho2;
        r.status = ObstacleStatus::kObstacle;
        r.nearest_occupied = c;
        r.nearest_distance_m = ground ? d.head<2>().norm() : d.norm();
      }
    }
  }
  return r;
}

}  // namespace scancrew::motion
