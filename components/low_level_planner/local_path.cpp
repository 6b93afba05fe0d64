#include "components/low_level_planner/local_path.hpp"

#include "core/motion/path_recheck.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::low_level_planner {

std::vector<Eigen::Vector3d> remaining_path(const std::vector<msg::Waypoint>& path,
                                            const Eigen::Vector3d& position) {
  std::vector<Eigen::Vector3d> rest;
  if (path.empty()) return rest;
  const size_t from = motion::first_waypoint_ahead(path, position);
  rest.reserve(path.size() - from);
  for (size_t k = from; k < path.size(); ++k) rest.push_back(msg::to_eigen(path[k].position));
  return rest;
}

double path_length_m(const msg::Vec3& start, const std::vector<msg::Waypoint>& path) {
  double length = 0;
  Eigen::Vector3d at = msg::to_eigen(start);
  for (const msg::Waypoint& w : path) {
    const Eigen::Vector3d next = msg::to_eigen(w.position);
    length += (next - at).norm();
    at = next;
  }
  return length;
}

}  // namespace scancrew::low_level_planner
