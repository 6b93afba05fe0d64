#include "components/low_level_planner/tour.hpp"

#include <algorithm>
#include <cmath>

namespace scancrew::low_level_planner {

uint64_t voxel_key(const msg::Vec3& p, double voxel_m) {
  // 21 bits per axis (±1 048 576 voxels: ±105 km at 0.1 m), offset to be non-negative
  constexpr int64_t kOffset = int64_t{1} << 20;
  constexpr uint64_t kMask = (uint64_t{1} << 21) - 1;
  const auto axis = [&](double v) {
    return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v / voxel_m)) + kOffset) & kMask;
  };
  return (axis(p.x) << 42) | (axis(p.y) << 21) | axis(p.z);
}

std::vector<uint64_t> voxel_keys(std::span<const msg::Vec3> points, double voxel_m) {
  std::vector<uint64_t> keys;
  keys.reserve(points.size());
  for (const msg::Vec3& p : points)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      keys.push_back(voxel_key(p, voxel_m));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

Tour make_tour(uint64_t plan_id, const msg::PathSequence& sequence, double voxel_m) {
  Tour t;
  t.plan_id = plan_id;
  t.sequence = sequence;
  t.c_start = voxel_keys(sequence.ise_centers_m, voxel_m);
  return t;
}

TourProgress tour_progress(uint32_t robot_id, const msg::Vec3& position,
                           const msg::PathSequence& sequence, size_t next) {
  TourProgress p;
  p.robot_id = robot_id;
  p.position = {position.x, position.y, position.z};
  p.tour.reserve(sequence.viewpoints.size());
  for (size_t i = 0; i < sequence.viewpoints.size(); ++i) {
    const msg::Vec3& g = sequence.viewpoints[i].position;
    p.tour.push_back(
        {.cluster_id = i < sequence.viewpoint_clusters.size() ? sequence.viewpoint_clusters[i] : 0,
         .goal = {g.x, g.y, g.z}});
  }
  p.next = std::min(next, p.tour.size());
  return p;
}

}  // namespace scancrew::low_level_planner
