#pragma once

// TrafficPolicy (thesis 3.5.2 item 5; Algorithm 3 lines 15-19, Algorithm 6 lines 19-23):
// from the team's shared states (pose, velocity, remaining path), a robot detects when a
// teammate is near, faces it, or will cross its path, and answers with a maneuver: step
// aside into free space to avoid a frontal collision, stop and wait while a teammate
// crosses its path, or proceed. The safety distance grows with speed: d = d0 + k·v.
//
// The thesis gives the behaviour, not the rules; ours (docs/traffic_policy.md):
// - Conflict of a pair: robots i and k conflict when i's remaining path cut at d_i comes
//   within r_i + r_k + margin of k's cut at d_k (speeds at least the nominal ones). The
//   pair is always evaluated in a canonical order (lower id first), so both robots reach
//   the same verdict from the same broadcast states.
// - Encounter: by the angle between the two paths where they meet: frontal (near
//   opposite), following (near parallel), crossing (else); a robot without a path
//   (holding) blocks.
// - Priority: frontal: the lower id proceeds, the other steps aside. Following: the robot
//   ahead proceeds, the follower stops. Crossing: the robot that reaches the conflict first
//   (arc length / nominal speed) proceeds, ties within tie_time_s go to the lower id; the
//   other stops before the conflict, or steps aside if it is already inside the
//   teammate's corridor. Blocking: the holding robot steps aside.
// - A yielding robot acts once its own conflict lies within d_i (current speed), and holds
//   until no conflict lies within d_i at nominal speed (hysteresis), and, after a crossing,
//   until the teammate is out of its camera's field of view or farther than that distance
//   (the thesis's "until it exits from its field of view").
// - Safety net: whatever the priority, a robot stops while a teammate's body lies in its
//   corridor ahead within d_i.
// - A hold longer than max_wait_s asks once for re-planning (a narrow corridor where no
//   aside point exists): no two robots wait forever.
//
// Deterministic: ties go to the lower id, and the result does not depend on the order of
// the teammates. Not thread safe (one policy per robot, called from its planner's thread);
// allocates two small polylines per teammate and call (a few Hz: not a hot path).

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/motion/check_types.hpp"
#include "core/motion/polyline.hpp"

namespace scancrew::motion {

// One robot as the policy sees it (own state or a teammate's broadcast one).
struct TrafficAgent {
  uint32_t id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw_rad = 0;
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  // world frame
  double nominal_speed_mps = 0.5;  // table 5.3 (ground); 0.6 for multirotors (2.6.1)
  // radius of the disc (ground) / ball (aerial) holding the body: 0.3 m holds the
  // 0.44 x 0.40 m ground robot of sim/robot_model.hpp
  double body_radius_m = 0.3;
  std::vector<Eigen::Vector3d> path;  // remaining waypoints, goal last; empty: holding
};

struct TrafficConfig {
  RobotKind kind = RobotKind::kGround;
  // safety distance d = d0 + k·v (m), v the robot's speed; d0 defaults to ObstacleCheck's
  // collision distance ("similarly to ObstacleCheck", 3.5.2): the 0.55 m semi-major axis
  // (table 5.3) or the 1 m collision radius (table 4.1); k: the thesis is silent
  double d0_m = 0.55;
  double k_s = 2.0;
  double margin_m = 0.2;            // gap kept between bodies
  double frontal_angle_deg = 45.0;  // within this of opposite: frontal; of parallel: following
  double tie_time_s = 0.5;          // arrival times closer than this: the lower id proceeds
  double sample_step_m = 0.05;      // path sampling for conflicts and aside segments
  // aside points: from clearance + aside_extra_m out to clearance + aside_max_m, in steps
  double aside_extra_m = 0.05;
  double aside_max_m = 1.0;
  double aside_step_m = 0.1;
  // no aside point nearer the robot than this: one within the tracker's position tolerance
  // (0.1 m) would be "reached" without a move
  double aside_min_move_m = 0.2;
  bool wait_until_out_of_view = true;
  double fov_deg = 90.0;     // horizontal camera FOV (table 5.3)
  double max_wait_s = 30.0;  // a longer hold asks for re-planning

  double safety_distance_m(double speed_mps) const { return d0_m + k_s * speed_mps; }
  // Thesis defaults for the kind (the struct's defaults are the ground robot's).
  static TrafficConfig for_kind(RobotKind kind);
  // Empty when valid, else every problem, "; "-separated.
  std::string validate() const;
};

enum class TrafficAction : uint8_t {
  kProceed,      // no maneuver (maneuver = None)
  kStopAndWait,  // hold position
  kStepAside,    // go to aside_point and hold there
  kResume,       // the hold is over: return to the path (sent once)
};
const char* to_string(TrafficAction action);

enum class Encounter : uint8_t { kNone, kFrontal, kFollowing, kCrossing, kBlocking, kIntrusion };
const char* to_string(Encounter encounter);

struct TrafficDecision {
  TrafficAction action = TrafficAction::kProceed;
  uint32_t because_of_robot = 0;
  Encounter encounter = Encounter::kNone;
  Eigen::Vector3d aside_point = Eigen::Vector3d::Zero();  // kStepAside
  double aside_yaw_rad = 0;
  bool request_replan = false;  // held longer than max_wait_s (once per hold)
  bool no_aside_point = false;  // had to step aside, found no free point: stopped instead
  double held_s = 0;            // how long the current hold has lasted
};

// The verdict on one pair, the same whichever robot computes it.
struct PairConflict {
  bool found = false;
  Encounter encounter = Encounter::kNone;
  uint32_t priority_id = 0;  // the robot that proceeds
  // arc lengths along each robot's path to where it enters the conflict (0: already in)
  double s_first_m = 0;   // the lower id's
  double s_second_m = 0;  // the higher id's
  double s_of(uint32_t id, uint32_t first_id) const {
    return id == first_id ? s_first_m : s_second_m;
  }
};
PairConflict pair_conflict(const TrafficAgent& a, const TrafficAgent& b,
                           const TrafficConfig& config);

class TrafficPolicy {
 public:
  enum class Mode : uint8_t { kFree, kWaiting, kAside };

  explicit TrafficPolicy(TrafficConfig config) : config_(config) {}

  // TrafficPolicy(q_i, q_k, M) at time now_s (monotonic, the caller's clock). `free` tells
  // where the robot's body fits (for the aside point); may be empty (then no aside point is
  // ever found and the robot stops instead). Teammates with this robot's id or non-finite
  // states are ignored.
  TrafficDecision update(const TrafficAgent& self, std::span<const TrafficAgent> teammates,
                         const FreeSpaceQuery& free, double now_s);

  // Forget the hold (a new path arrived after a re-planning request).
  void reset();
  Mode mode() const { return mode_; }
  const TrafficConfig& config() const { return config_; }

 private:
  struct Candidate {
    TrafficAction action = TrafficAction::kProceed;
    Encounter encounter = Encounter::kNone;
    uint32_t robot = 0;
    double s_m = 0;
  };
  struct Reasons {  // the most urgent reason of each kind, and whether there is one
    Candidate aside, stop, net;
    bool want_aside = false, want_stop = false, want_net = false;
  };
  bool find_aside_point(const TrafficAgent& self, std::span<const TrafficAgent> teammates,
                        const TrafficAgent& priority, const FreeSpaceQuery& free,
                        Eigen::Vector3d& aside);
  bool aside_fits(const Eigen::Vector3d& q, double extra, const TrafficAgent& self,
                  std::span<const TrafficAgent> teammates, const TrafficAgent& priority,
                  const FreeSpaceQuery& free);
  Reasons reasons(const TrafficAgent& self, std::span<const TrafficAgent> teammates, double reach);
  std::optional<TrafficDecision> decide(const Reasons& r, const TrafficAgent& self,
                                        std::span<const TrafficAgent> teammates,
                                        const FreeSpaceQuery& free, double now_s);
  bool in_view(const TrafficAgent& self, const TrafficAgent& other, double range_m) const;
  bool on_way_ahead_of(const TrafficAgent& k, const TrafficAgent& self);
  TrafficDecision hold(TrafficAction action, const Candidate& c, double now_s);

  TrafficConfig config_;
  Mode mode_ = Mode::kFree;
  uint32_t held_by_ = 0;
  Encounter held_encounter_ = Encounter::kNone;
  Eigen::Vector3d aside_ = Eigen::Vector3d::Zero();
  double aside_yaw_ = 0;
  double hold_since_s_ = 0;
  bool replan_sent_ = false;
  Polyline own_, other_;  // scratch
};

}  // namespace scancrew::motion
