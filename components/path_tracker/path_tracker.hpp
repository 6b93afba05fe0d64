#pragma once

// PathTracker: the robot's controller (the "Controller" of thesis 2.5.3 Algorithm 1,
// 3.5.2 Algorithm 3, 4.5.2 Algorithm 6). It follows the low-level planner's local path
// with a pose-based visual-servoing law towards a look-ahead pose on it
// (look_ahead.hpp, tracking_law.hpp), mapped to the robot's commands with the speed limits
// of its type (velocity_mapping.hpp), and obeys the traffic policy's maneuvers at once.
//
// Ports (relative: in the robot's namespace)
//   in   local_path     msg::LocalPath   a new plan_id replaces the path; an older one is
//                                        stale (ignored, logged once); the same plan_id is
//                                        a re-send (ignored when unchanged, else replaces)
//   in   pose           msg::Odometry    the robot's pose (remap: pose_gt, or odom from vio)
//   in   maneuver       msg::Maneuver    kStop: zero command now, held until kResume;
//                                        kStepAside: go to the aside pose, then hold;
//                                        kResume: back to the path (progress goes on)
//   out  cmd_vel        msg::VelocityCommand  every tick (zero whenever not moving)
//   out  tracker_state  msg::RobotState  every tick (publish_state): pose, velocity, mode, plan_id,
//                                        path_index (next waypoint), steps_remaining,
//                                        path_length_m (distance travelled since start)
// Modes: kIdle (no path, or an empty / invalid one), kMoving, kDone (the plan's final
// waypoint reached within position_tolerance_m and yaw_tolerance_deg; zero command until
// a new plan), kStopped, kSteppingAside, kWaiting (at the aside pose), kLost (no pose, a
// NaN pose, tracking lost or a pose older than pose_timeout_s: zero command, logged once;
// with lost_turn_rate_radps > 0 a ground robot whose odometry lost track, and did not find
// it again at rest within lost_turn_after_s, turns on the spot at that rate until it
// resumes).
// First scan (initial_turn_deg > 0, ground robots): from its first usable pose the robot
// turns on the spot at its ground_max_yaw_rate_radps until it has turned that far, before it
// follows any path (a path that comes meanwhile waits); a stop order pauses the turn, a
// step-aside ends it. Without it, a start that sees only a few ISEs with feasible viewpoints
// could finish them and leave C_ins empty: the parking lot's single robot, seed 3, met the
// ISE criterion at 13.8 s with 12 % coverage (docs/path_tracker.md).
// A goal close behind a ground robot with its yaw (a back-off) is reached backwards
// (ground_reverse_max_m, velocity_mapping.hpp).
// A new plan clears a stop or step-aside when new_plan_resumes is true (the planner
// replans after an emergency stop, Algorithm 1 line 16).
//
// Between two poses (the simulator sends them at camera rate, 5 Hz) the pose is predicted
// from the commands sent since its stamp (predict_pose).
//
// Latency: each command computed from a fresh pose records its age (publish time minus
// the pose's capture stamp); the first command after each new pose is camera to command.
// summarize() reports both (RunSummary::CommandLatency, metrics.json).
//
// Thread safety: the callbacks run in the component's mutually exclusive group (the
// default); the accessors are for tests after a run.

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "components/path_tracker/look_ahead.hpp"
#include "components/path_tracker/tracking_law.hpp"
#include "components/path_tracker/velocity_mapping.hpp"
#include "executors/component.hpp"
#include "executors/latency_histogram.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::path_tracker {

class PathTracker final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "follows the local path (PBVS with ViSP towards a look-ahead pose); obeys stop and "
      "step-aside maneuvers; publishes cmd_vel and tracker_state";
  struct Config {
    double rate_hz = 20.0;  // command rate
    LookAheadConfig look_ahead;
    TrackingLawConfig law;
    GroundMappingConfig ground;
    MultirotorMappingConfig multirotor;
    double position_tolerance_m =
        0.1;                           // goal and aside pose reached (horizontal for ground robots)
    double yaw_tolerance_rad = 0.087;  // 5 deg
    double pose_timeout_s = 1.0;       // older poses: stop (kLost)
    double lost_turn_rate_radps = 0;   // ground, tracking lost: turn on the spot (0: hold)
    double lost_turn_after_s = 2.0;    // ... after holding still this long
    double initial_turn_deg = 0;       // ground: turn this far on the spot first (0: no)
    bool predict_pose = true;
    bool new_plan_resumes = true;
    bool publish_state = true;  // false: no tracker_state (a mission reads none)
  };
  static Config read_config(ParamReader& p);

  PathTracker(ComponentContext context, Config config);

  // For tests and reports.
  msg::RobotState::Mode mode() const { return mode_; }
  uint64_t plan_id() const { return plan_id_; }
  uint32_t plans_done() const { return plans_done_; }
  double travelled_m() const { return travelled_m_; }
  // The errors when the last plan was declared done (position m, |yaw| rad), and when.
  double done_position_error_m() const { return done_position_error_m_; }
  double done_yaw_error_rad() const { return done_yaw_error_rad_; }
  int64_t done_stamp_ns() const { return done_stamp_ns_; }
  uint32_t stale_plans() const { return stale_plans_; }
  bool ground() const { return ground_; }
  // Age of the pose behind each command (ns): every command; the first after each new pose.
  const LatencyHistogram& command_age() const { return command_age_; }
  const LatencyHistogram& first_use_age() const { return first_use_age_; }
  void summarize(RunSummary& into) const override;

 private:
  struct SentCommand {
    int64_t stamp_ns = 0;
    double vx = 0, vy = 0, vz = 0, yaw_rate = 0;
  };

  Result<void, std::string> on_configure() override;
  void on_path(const msg::LocalPath& path);
  void on_pose(const msg::Odometry& odom);
  void on_maneuver(const msg::Maneuver& maneuver);
  void on_tick();
  // The pose now: the last one, moved by the commands sent since its stamp.
  Eigen::Isometry3d predicted_pose(int64_t now_ns) const;
  // Command towards a target pose; returns it in `cmd`. `goal` (the final waypoint, or the
  // aside point): with may_reverse (a straight way to it), a ground robot reaches one close
  // behind it, with its yaw, backwards. `final_pose`: the target is the goal itself (a
  // ground robot turns to its yaw once near), not a look-ahead point on the way.
  void steer(const Eigen::Isometry3d& T_world_body, const Eigen::Vector3d& target_m,
             double target_yaw_rad, const msg::Waypoint& goal, bool may_reverse, bool final_pose,
             msg::VelocityCommand& cmd);
  bool reverse_to(const Eigen::Isometry3d& T_world_body, const msg::Waypoint& goal);
  // Position and yaw errors to a pose (horizontal for ground robots).
  std::pair<double, double> errors_to(const Eigen::Isometry3d& T_world_body,
                                      const msg::Waypoint& w) const;
  void publish(const msg::VelocityCommand& cmd, int64_t now_ns, msg::RobotState::Mode mode);
  void warn_once(bool& flag, const char* what);
  void record_age(int64_t now_ns);

  Config config_;
  bool ground_ = true;
  LookAhead look_ahead_;
  TrackingLaw law_;
  Publisher<msg::VelocityCommand> cmd_;
  Publisher<msg::RobotState> state_;

  // plan
  std::vector<msg::Waypoint> path_;
  uint64_t plan_id_ = 0;
  bool have_plan_ = false, path_ok_ = false, done_ = false;
  uint32_t plans_done_ = 0, stale_plans_ = 0;
  uint32_t next_index_ = 0;
  double done_position_error_m_ = 0, done_yaw_error_rad_ = 0;
  int64_t done_stamp_ns_ = 0;
  // maneuver
  enum class Order : uint8_t { kNone, kStop, kStepAside };
  Order order_ = Order::kNone;
  msg::Waypoint aside_;
  // pose
  msg::Odometry pose_;
  bool pose_seen_ = false;      // any pose message, usable or not
  bool tracking_lost_ = false;  // the last pose message: finite, tracking quality 0
  int64_t lost_since_ns_ = 0;   // when tracking_lost_ became true
  bool reversing_ = false;      // backing to the goal (reverse_to's hysteresis)
  bool turning_first_ = false;  // the first scan's turn is under way (or yet to start)
  double turned_rad_ = 0;       // ... how far it has turned
  std::optional<double> turn_last_yaw_;
  bool have_pose_ = false;        // a usable pose was received
  bool pose_valid_ = false;       // the last pose message was usable
  std::deque<SentCommand> sent_;  // commands since the pose's stamp (prediction)
  Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
  double travelled_m_ = 0;
  // latency (camera to command)
  LatencyHistogram command_age_, first_use_age_;
  uint64_t poses_used_ = 0;
  bool pose_unused_ = false;  // a pose arrived that no command has used yet
  msg::RobotState::Mode mode_ = msg::RobotState::Mode::kIdle;
  // logged once
  bool logged_lost_ = false, logged_stale_pose_ = false, logged_stale_plan_ = false,
       logged_bad_path_ = false, logged_bad_aside_ = false;
};

}  // namespace scancrew::path_tracker
