#pragma once

// From the tracking law's body twist (tracking_law.hpp) to the commands a robot takes,
// with the speed limits of its type (nominal speeds: thesis table 5.3, 0.5 m/s for the
// ground robots; tables 3.1/4.1, 0.6 m/s for the multirotors).
//
// Ground robot (unicycle, differential drive: v forward, ω yaw rate; no lateral motion).
// With o the target's horizontal offset in the body frame, d = |o|, α = atan2(o_y, o_x):
//   far   (d ≥ align_radius):    steer at the target point (a go-to-point law)
//           v = 0 if |α| > turn_in_place_rad (turn on the spot), else min(|v_xy|, v_max)·cos α
//           ω = heading_gain · α
//   near  (d ≤ align_radius/2):  the PBVS twist's own unicycle part: v = v_x (may reverse),
//           ω = ω_z (turns to the target's yaw)
//   between: a linear blend of the two speeds; the yaw rate is the near law's from
//           d < align_radius on (a blend of the yaw rates had an equilibrium with the target
//           square to the side: still, short of its yaw). Then |v| ≤ max_speed,
//           |ω| ≤ max_yaw_rate.
// The far law ignores the target's yaw: on a path the look-ahead point pulls the robot
// along; at the goal the near law turns it to the final yaw with at most align_radius of
// position error. The near law is for a final pose only (`final_pose`: the path's end, an
// aside point): a look-ahead point on the way that lies within align_radius (a path that
// doubles back beside the robot) takes the far law alone, which drives the robot onto it,
// so that its projection moves on; the near law held the robot still beside such a point,
// turned to its yaw, for 1400 s (parking lot, single robot, seed 5).
// Reversing (the caller's choice, `reverse`: a short move to a point behind, keeping the
// yaw, as a back-off from an obstacle): the far law steers the robot's back at the point,
// α' = α − π wrapped, v = −min(|v_xy|, v_max)·cos α' (0 if |α'| > turn_in_place_rad),
// ω = heading_gain · α', at most |v| / reverse_min_radius_m (an arc, not a turn on the
// spot). A robot turning on the spot sweeps its corners round (0.30 m for the 0.44 × 0.40 m
// robot); backing out along an arc of 0.5 m from 0.25 m beside a wall keeps its front
// corner off the wall.
// Multirotor (holonomic, yaw-controlled): (v_x, v_y, v_z) = the PBVS linear twist scaled
// down (direction kept) so that |v| ≤ max_speed and |v_z| ≤ max_vertical_speed;
// yaw rate = ω_z clamped to max_yaw_rate.
//
// Pure functions; thread safe; no allocation.

#include <Eigen/Core>

#include "components/path_tracker/tracking_law.hpp"

namespace scancrew::path_tracker {

struct GroundMappingConfig {
  double max_speed_mps = 0.5;  // thesis table 5.3 (robot nominal speed)
  double max_yaw_rate_radps = 1.0;
  double heading_gain = 2.0;       // 1/s
  double turn_in_place_rad = 1.0;  // heading error above which the robot turns on the spot
  double align_radius_m = 0.1;     // within it the robot turns to the target's yaw
  // a goal this close behind the robot, with (about) its yaw, is reached backwards (the
  // low-level planner's back-off poses lie within backoff_max_m, 1 m); 0: never reverse
  double reverse_max_m = 1.0;
  // backing turns on arcs at least this wide (0: no limit): a back-off 45 degrees off
  // straight back, turned at the full yaw rate from 0.25 m beside a wall, swung the robot's
  // front corner into it (parking lot, distributed pair, seed 2)
  double reverse_min_radius_m = 0.5;
};

struct MultirotorMappingConfig {
  double max_speed_mps = 0.6;  // thesis tables 3.1, 4.1 (UAV nominal speed)
  double max_vertical_speed_mps = 0.5;
  double max_yaw_rate_radps = 1.0;
};

struct UnicycleCommand {
  double v_mps = 0;        // forward
  double omega_radps = 0;  // yaw rate
};

struct MultirotorCommand {
  Eigen::Vector3d linear_mps = Eigen::Vector3d::Zero();  // body heading frame
  double yaw_rate_radps = 0;
};

UnicycleCommand to_unicycle(const LawOutput& law, const GroundMappingConfig& config,
                            bool reverse = false, bool final_pose = true);
MultirotorCommand to_multirotor(const LawOutput& law, const MultirotorMappingConfig& config);

}  // namespace scancrew::path_tracker
