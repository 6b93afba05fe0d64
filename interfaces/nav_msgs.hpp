#pragma once

// Navigation messages: odometry, plans, paths, commands and robot state.

#include <cstdint>
#include <vector>

#include "interfaces/geometry.hpp"
#include "interfaces/header.hpp"

namespace scancrew::msg {

struct Odometry {
  static constexpr const char* kTypeName = "scancrew/Odometry";
  Header header;  // stamp: the image time the pose refers to
  Pose3 T_world_body;
  Vec3 linear_velocity_mps;
  Vec3 angular_velocity_radps;
  Mat6 pose_covariance{};
  double tracking_quality = 0;   // 0 (lost) .. 1 (all tracks inliers)
  uint32_t tracking_resets = 0;  // re-initialisations after lost tracking, so far
};

// A pose along a path for the tracker: x, y, z, yaw (ground robots keep z constant).
struct Waypoint {
  Vec3 position;
  double yaw_rad = 0;
};

// The low-level planner's path to the current goal, for the tracker.
struct LocalPath {
  static constexpr const char* kTypeName = "scancrew/LocalPath";
  Header header;
  uint64_t plan_id = 0;
  std::vector<Waypoint> waypoints;
};

// One robot's ordered tour of viewpoint clusters (thesis 2.5.2) and the viewpoints to
// visit inside each.
struct PathSequence {
  uint32_t robot_id = 0;
  std::vector<uint32_t> cluster_ids;         // in visiting order
  std::vector<double> cluster_utilities;     // f of the arc into each cluster (eq. 2.3)
  std::vector<Waypoint> viewpoints;          // in visiting order
  std::vector<uint32_t> viewpoint_clusters;  // the cluster id of each viewpoint
  // C_start: the ISE centres the tour's viewpoints see (UtilityCheck, thesis 2.5.3 item 3)
  std::vector<Vec3> ise_centers_m;
  double utility = 0;  // p = maxATSP(U)
};

// The team plan from TSGA / dist-TSGA / NNB (thesis 2.5.2, 3.5.1, 4.5.1). Centralized: one
// sequence per robot; distributed: the sending robot's own.
struct TeamPlan {
  static constexpr const char* kTypeName = "scancrew/TeamPlan";
  Header header;
  uint64_t plan_id = 0;
  uint64_t map_version = 0;  // the clusters' map snapshot
  std::vector<PathSequence> sequences;
  std::vector<uint32_t> unassigned;  // clusters no robot of the team can reach
};

struct VelocityCommand {
  static constexpr const char* kTypeName = "scancrew/VelocityCommand";
  Header header;
  Vec3 linear_mps;  // body frame; a ground robot uses x only
  double yaw_rate_radps = 0;
};

// Traffic-policy orders to the tracker (thesis 3.5.2).
struct Maneuver {
  static constexpr const char* kTypeName = "scancrew/Maneuver";
  enum class Kind : uint8_t { kResume, kStop, kStepAside };
  Header header;
  Kind kind = Kind::kResume;
  Waypoint aside;  // where to step aside to (kStepAside)
  uint32_t because_of_robot = 0;
};

// A robot's state for its team (traffic policy, redundancy check, reallocation) and for the
// high-level planner (kIdle: reallocate). kPlanning: waiting for the plan its ReplanRequest
// asked for.
struct RobotState {
  static constexpr const char* kTypeName = "scancrew/RobotState";
  enum class Mode : uint8_t {
    kIdle,
    kPlanning,
    kMoving,
    kWaiting,
    kSteppingAside,
    kStopped,
    kDone,
    kLost
  };
  Header header;
  Pose3 T_world_body;
  Vec3 velocity_mps;  // world frame
  Mode mode = Mode::kIdle;
  uint64_t plan_id = 0;          // the plan (tour or local path) being followed
  uint32_t current_cluster = 0;  // the cluster of the current goal
  uint32_t path_index = 0;       // progress: index of the next waypoint / viewpoint
  uint32_t steps_remaining = 0;  // waypoints / viewpoints left
  double path_length_m = 0;      // travelled so far
  // what holds the robot, beside its mode (the mission's time breakdown): a back-off path
  // (mode kMoving), or a teammate the traffic policy yields to (kWaiting, kSteppingAside)
  bool backing_off = false;
  uint32_t held_by_robot = 0;  // 0: none
};

inline const char* to_string(RobotState::Mode mode) {
  switch (mode) {
    case RobotState::Mode::kIdle:
      return "idle";
    case RobotState::Mode::kPlanning:
      return "planning";
    case RobotState::Mode::kMoving:
      return "moving";
    case RobotState::Mode::kWaiting:
      return "waiting";
    case RobotState::Mode::kSteppingAside:
      return "stepping-aside";
    case RobotState::Mode::kStopped:
      return "stopped";
    case RobotState::Mode::kDone:
      return "done";
    case RobotState::Mode::kLost:
      return "lost";
  }
  return "?";
}

// A robot's request for a new tour, with why: the "wait for high-level re-planning" of
// Algorithms 1, 3 and 6 (thesis 2.5.3, 3.5.2, 4.5.2). The low-level planner sends it on
// `replan_request` (again after replan_timeout_s unanswered); the high-level planner answers
// with a plan newer than after_plan_id.
struct ReplanRequest {
  static constexpr const char* kTypeName = "scancrew/ReplanRequest";
  enum class Reason : uint8_t {
    kUtility,       // UtilityCheck: c_thres of the tour's ISEs are done (Alg. 1 line 5)
    kObstacle,      // ObstacleCheck: emergency stop (Alg. 1 line 15)
    kRedundancy,    // RedundancyCheck: the next cluster is a teammate's (Alg. 6 line 5)
    kTrafficStuck,  // TrafficPolicy: held longer than max_wait_s (not in the thesis)
    kInfeasible,    // no path to the tour's goals (Alg. 1 line 10, else branch), or the
                    // last one skipped
  };
  Header header;
  Reason reason = Reason::kUtility;
  uint32_t because_of_robot = 0;  // the teammate involved (kRedundancy, kTrafficStuck), else 0
  uint64_t after_plan_id = 0;     // the newest plan the robot had seen
  bool repeated = false;          // sent again: the first went unanswered
};

inline const char* to_string(ReplanRequest::Reason reason) {
  switch (reason) {
    case ReplanRequest::Reason::kUtility:
      return "utility";
    case ReplanRequest::Reason::kObstacle:
      return "obstacle";
    case ReplanRequest::Reason::kRedundancy:
      return "redundancy";
    case ReplanRequest::Reason::kTrafficStuck:
      return "traffic_stuck";
    case ReplanRequest::Reason::kInfeasible:
      return "infeasible";
  }
  return "?";
}

struct MissionStatus {
  static constexpr const char* kTypeName = "scancrew/MissionStatus";
  enum class Phase : uint8_t { kStarting, kExploring, kDone, kAborted };
  Header header;
  Phase phase = Phase::kStarting;
  uint32_t ise_remaining = 0;
  double coverage_estimate = 0;
  double elapsed_s = 0;
};

// The lockstep of a team split over processes (docs/processes.md): the simulator's bridge
// (the leader) tells the robots' bridges to step their sim clocks to t_ns; each follower
// answers with the same message once it has stepped. `marks` say, per sender and DDS topic
// (its key, LinkModel::topic_key), the last sequence number written up to this step: a
// bridge steps only once it has received those samples, and holds back later ones, so what
// a process sees at each step does not depend on the processes' relative speed.
struct StepMark {
  uint32_t robot_id = 0;   // the sending bridge
  uint64_t topic_key = 0;  // its DDS topic's key
  uint64_t seq = 0;        // the last sequence number written on it
};
struct StepSync {
  static constexpr const char* kTypeName = "scancrew/StepSync";
  Header header;     // header.robot_id: the sending bridge's id
  int64_t t_ns = 0;  // leader: step to t_ns; follower: stepped to t_ns
  uint8_t stop = 0;  // leader: the run ends (follower: it has ended)
  std::vector<StepMark> marks;
};

}  // namespace scancrew::msg
