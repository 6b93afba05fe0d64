#pragma once

// A robot's remaining path as a polyline (its position, then its waypoints), cut at a given
// arc length, with the queries the traffic policy needs: the point and tangent at an arc
// length, and the closest point to a query point. Planar polylines (ground robots) drop z:
// every distance is measured in the plane. Plain value type; assign() reuses capacity.

#include <Eigen/Core>
#include <span>
#include <vector>

namespace scancrew::motion {

class Polyline {
 public:
  // start, then waypoints, cut at max_length_m (>= 0; a point when 0). Consecutive
  // duplicate points are dropped.
  void assign(const Eigen::Vector3d& start, std::span<const Eigen::Vector3d> waypoints,
              double max_length_m, bool planar);

  bool empty() const { return points_.empty(); }
  double length_m() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }
  std::span<const Eigen::Vector3d> points() const { return points_; }

  // The point at arc length s (clamped to [0, length]).
  Eigen::Vector3d at(double s) const;
  // The unit direction of travel at arc length s; zero for a single point.
  Eigen::Vector3d tangent(double s) const;

  struct Closest {
    double distance_m = 0;
    double s_m = 0;  // arc length of the closest point
  };
  // The closest point of the polyline to p (the first one on ties). Requires !empty().
  Closest closest(const Eigen::Vector3d& p) const;

  // Flattens p for planar polylines.
  Eigen::Vector3d project(const Eigen::Vector3d& p) const;

 private:
  size_t segment_at(double s) const;

  bool planar_ = false;
  std::vector<Eigen::Vector3d> points_;
  std::vector<double> cumulative_;  // arc length at each point
};

}  // namespace scancrew::motion
