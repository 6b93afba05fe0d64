#pragma once

// ObstacleGeometry: exact obstacles (boxes, vertical cylinders, triangle meshes) and a
// robot body tested against them with FCL — the ground truth the planner's paths are
// checked against in tests and in `scancrew bench planner` (the "done when":
// paths collision-free against the ground-truth geometry). Not used by the planner itself,
// which only sees the map.
//
// Not thread safe (FCL objects are moved to each pose).

#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/motion/planner_config.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::motion {

// The body's pose at a path waypoint: a ground robot's body centre at
// ground_body_center_z_m, a multirotor's at the waypoint; yaw about z.
Eigen::Isometry3d body_pose(const PlannerConfig& config, const msg::Waypoint& w);

struct PathCheck {
  size_t samples = 0;
  size_t colliding = 0;  // samples whose body overlaps an obstacle
  msg::Waypoint first_colliding;
};

class ObstacleGeometry {
 public:
  ObstacleGeometry();
  ~ObstacleGeometry();
  ObstacleGeometry(ObstacleGeometry&&) noexcept;
  ObstacleGeometry& operator=(ObstacleGeometry&&) noexcept;

  // Full sizes, turned by yaw about z around the centre.
  void add_box(const Eigen::Vector3d& center_m, const Eigen::Vector3d& size_m, double yaw_rad = 0);
  // Axis along z, centred at center_m.
  void add_cylinder(const Eigen::Vector3d& center_m, double radius_m, double height_m);
  // A triangle soup (world coordinates).
  void add_mesh(const std::vector<Eigen::Vector3d>& vertices,
                const std::vector<std::array<uint32_t, 3>>& triangles);
  size_t size() const;

  bool collides(const robot::BodyModel& body, const Eigen::Isometry3d& T_world_body) const;

  // Samples the path every step_m along each segment (position linear, yaw along the
  // shorter arc) and tests the body at each sample.
  PathCheck check_path(const PlannerConfig& config, const robot::BodyModel& body,
                       const std::vector<msg::Waypoint>& path, double step_m) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::motion
