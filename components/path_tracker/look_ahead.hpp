#pragma once

// LookAhead: the tracker's reference on a local path (the low-level planner's LocalPath,
// thesis 2.5.3 Algorithm 1: a polyline of x, y, z, yaw waypoints). Each update projects
// the robot's position on the path — the nearest point, searched forward from the
// current progress within search_window_m, so the progress never goes back and a path
// that loops near itself is not short-cut — and returns the pose distance_m further
// along the path: the target of the tracking law (tracking_law.hpp). The target's yaw is
// the direction of travel of its segment (yaw_source kTangent: the forward camera looks
// where the robot goes) or the yaw of the segment's end waypoint (kWaypoints); within
// distance_m of the end the target is the final waypoint, with its yaw.
//
// Ground robots (planar): projection and arc length in x-y; the target's z is the
// waypoints' (the tracker replaces it with the robot's own).
// Not thread safe; set_path() allocates, update() does not.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/enum_names.hpp"
#include "core/result.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::path_tracker {

enum class YawSource : uint8_t { kTangent, kWaypoints };

inline constexpr EnumNames<YawSource, 2> kYawSourceNames = {
    {{YawSource::kTangent, "tangent"}, {YawSource::kWaypoints, "waypoints"}}};

struct LookAheadConfig {
  double distance_m = 0.5;       // look-ahead distance along the path
  double search_window_m = 2.0;  // how far past the progress the projection may move per update
  bool planar = false;           // ground robots: x-y only
  YawSource yaw_source = YawSource::kTangent;
};

struct LookAheadTarget {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0;
  bool at_end = false;       // the target is the final waypoint
  uint32_t next_index = 0;   // progress: index of the next waypoint ahead of the projection
  double progress_m = 0;     // arc length of the projection
  double remaining_m = 0;    // arc length from the projection to the end
  double cross_track_m = 0;  // distance from the robot to its projection
};

class LookAhead {
 public:
  explicit LookAhead(LookAheadConfig config = {});

  // Takes a new path; progress restarts at its start. An empty path or a non-finite
  // waypoint is refused with the reason (the previous path is then dropped too).
  Result<void, std::string> set_path(const std::vector<msg::Waypoint>& waypoints);
  void clear();
  bool has_path() const { return !points_.empty(); }
  size_t size() const { return points_.size(); }
  double length_m() const { return arc_m_.empty() ? 0.0 : arc_m_.back(); }
  const msg::Waypoint& final_waypoint() const { return waypoints_.back(); }
  const LookAheadConfig& config() const { return config_; }

  // Advances the progress to the robot's projection (monotone) and returns the target.
  // Needs has_path() and a finite position.
  LookAheadTarget update(const Eigen::Vector3d& position_m);

 private:
  Eigen::Vector3d flat(const Eigen::Vector3d& p) const;
  Eigen::Vector3d point_at(double s_m, size_t* segment) const;

  LookAheadConfig config_;
  std::vector<msg::Waypoint> waypoints_;
  std::vector<Eigen::Vector3d> points_;  // waypoint positions (z = 0 when planar)
  std::vector<double> arc_m_;            // arc length at each waypoint
  std::vector<double> tangent_yaw_;      // per segment
  size_t segment_ = 0;                   // segment of the progress
  double progress_m_ = 0;
};

}  // namespace scancrew::path_tracker
