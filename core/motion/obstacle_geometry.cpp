#include "core/motion/obstacle_geometry.hpp"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>
#include <cmath>

namespace scancrew::motion {

Eigen::Isometry3d body_pose(const PlannerConfig& config, const msg::Waypoint& w) {
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  T_world_body.translation() =
      Eigen::Vector3d(w.position.x, w.position.y,
                      config.robot_kind == RobotKind::kGround ? config.ground_body.safety_center_z_m
                                                              : w.position.z);
  T_world_body.linear() = Eigen::AngleAxisd(w.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T_world_body;
}

struct ObstacleGeometry::Impl {
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
};

ObstacleGeometry::ObstacleGeometry() : impl_(std::make_unique<Impl>()) {}
ObstacleGeometry::~ObstacleGeometry() = default;
ObstacleGeometry::ObstacleGeometry(ObstacleGeometry&&) noexcept = default;
ObstacleGeometry& ObstacleGeometry::operator=(ObstacleGeometry&&) noexcept = default;

void ObstacleGeometry::add_box(const Eigen::Vector3d& center_m, const Eigen::Vector3d& size_m,
                               double yaw_rad) {
  Eigen::Isometry3d T_world_obstacle = Eigen::Isometry3d::Identity();
  T_world_obstacle.translation() = center_m;
  T_world_obstacle.linear() =
      Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  impl_->objects.push_back(std::make_unique<fcl::CollisionObjectd>(
      std::make_shared<fcl::Boxd>(size_m.x(), size_m.y(), size_m.z()), T_world_obstacle));
}

void ObstacleGeometry::add_cylinder(const Eigen::Vector3d& center_m, double radius_m,
                                    double height_m) {
  Eigen::Isometry3d T_world_obstacle = Eigen::Isometry3d::Identity();
  T_world_obstacle.translation() = center_m;
  impl_->objects.push_back(std::make_unique<fcl::CollisionObjectd>(
      std::make_shared<fcl::Cylinderd>(radius_m, height_m), T_world_obstacle));
}

void ObstacleGeometry::add_mesh(const std::vector<Eigen::Vector3d>& vertices,
                                const std::vector<std::array<uint32_t, 3>>& triangles) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Triangle> tris;
  tris.reserve(triangles.size());
  for (const auto& t : triangles) tris.emplace_back(t[0], t[1], t[2]);
  model->beginModel(static_cast<int>(tris.size()), static_cast<int>(vertices.size()));
  model->addSubModel(vertices, tris);
  model->endModel();
  impl_->objects.push_back(std::make_unique<fcl::CollisionObjectd>(model));
}

size_t ObstacleGeometry::size() const {
  return impl_->objects.size();
}

bool ObstacleGeometry::collides(const robot::BodyModel& body, const Eigen::Isometry3d& T) const {
  const Eigen::Vector3d& r = body.safety_radii_m;
  std::shared_ptr<fcl::CollisionGeometryd> shape;
  if (r.x() == r.y() && r.y() == r.z())
    shape = std::make_shared<fcl::Sphered>(r.x());
  else
    shape = std::make_shared<fcl::Ellipsoidd>(r.x(), r.y(), r.z());
  fcl::CollisionObjectd o(shape, T);
  fcl::CollisionRequestd request;
  for (const auto& obstacle : impl_->objects) {
    fcl::CollisionResultd result;
    fcl::collide(&o, obstacle.get(), request, result);
    if (result.isCollision()) return true;
  }
  return false;
}

PathCheck ObstacleGeometry::check_path(const PlannerConfig& config, const robot::BodyModel& body,
                                       const std::vector<msg::Waypoint>& path,
                                       double step_m) const {
  PathCheck out;
  auto test = [&](const msg::Waypoint& w) {
    ++out.samples;
    if (collides(body, body_pose(config, w))) {
      if (out.colliding == 0) out.first_colliding = w;
      ++out.colliding;
    }
  };
  if (path.empty()) return out;
  test(path.front());
  for (size_t i = 1; i < path.size(); ++i) {
    const msg::Waypoint& a = path[i - 1];
    const msg::Waypoint& b = path[i];
    const Eigen::Vector3d pa(a.position.x, a.position.y, a.position.z);
    const Eigen::Vector3d pb(b.position.x, b.position.y, b.position.z);
    const double dyaw = std::remainder(b.yaw_rad - a.yaw_rad, 2 * M_PI);
    const int n = std::max(1, static_cast<int>(std::ceil((pb - pa).norm() / step_m)));
    for (int k = 1; k <= n; ++k) {
      const double t = static_cast<double>(k) / n;
      msg::Waypoint w;
      const Eigen::Vector3d p = pa + t * (pb - pa);
      w.position = {p.x(), p.y(), p.z()};
      w.yaw_rad = a.yaw_rad + t * dyaw;
      test(w);
    }
  }
  return out;
}

}  // namespace scancrew::motion
