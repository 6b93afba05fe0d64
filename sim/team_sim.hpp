#pragma once

// TeamSim: the MuJoCo team simulator — one scene, N robots, their stereo cameras
// (rendered headless through one GL context), ground-truth depth and pose, IMUs, the
// depth noise model, and a count of contacts as a safety metric.
//
// Ownership: owns the MuJoCo model and data (immutable model, mutable data, as MuJoCo
// does) and the GL context. Thread safety: none — one thread drives a TeamSim (the
// team_simulator component's callbacks, or a test); rendering moves the GL context to
// that thread. Allocation: stepping and setting commands allocate nothing; rendering
// resizes the output messages' vectors (no allocation once they have their capacity).

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"
#include "sim/mjcf_builder.hpp"
#include "sim/robot_model.hpp"
#include "sim/scene.hpp"

namespace scancrew::sim {

struct TeamSimConfig {
  MjcfOptions mjcf;
  uint64_t seed = 1;              // noise generators (IMU, depth), per robot from this seed
  bool rendering = true;          // false: no GL context (physics-only runs and tests)
  double max_speed_factor = 2.0;  // commands are clamped to this times the nominal speed
};

struct ContactCounts {
  uint64_t robot_robot = 0;  // contact onsets between two robots
  uint64_t robot_scene = 0;  // contact onsets between a robot and a scene solid
};

// One contact onset: where and with what a robot started touching something.
struct ContactOnset {
  double t_s = 0;
  size_t robot = 0;        // robot index
  std::string other;       // the scene solid's body name, or the other robot's name
  msg::Vec3 position;      // contact point, world frame (m)
  msg::Vec3 robot_xy_yaw;  // the robot's x, y (m) and yaw (rad) then
};

class TeamSim {
 public:
  // Fails with the cause: an invalid camera, a robot starting inside an obstacle or
  // outside the bounds, a mesh MuJoCo cannot load, no GL when rendering is on.
  static Result<std::unique_ptr<TeamSim>, std::string> create(const SceneSpec& scene,
                                                              std::vector<RobotSpec> robots,
                                                              const TeamSimConfig& config);
  ~TeamSim();
  TeamSim(const TeamSim&) = delete;
  TeamSim& operator=(const TeamSim&) = delete;

  size_t robot_count() const { return robots_.size(); }
  const RobotSpec& robot(size_t i) const { return robots_[i]; }
  const SceneSpec& scene() const { return scene_; }
  const std::string& mjcf() const { return mjcf_; }

  int64_t time_ns() const;
  int64_t timestep_ns() const;
  // Steps physics until sim time >= t_ns (whole timesteps).
  void step_until(int64_t t_ns);

  // Body-frame command: ground robots use linear.x and the yaw rate (differential drive);
  // multirotors linear x, y, z and the yaw rate. Held until the next command.
  void set_velocity(size_t robot, const msg::VelocityCommand& command);

  msg::Pose3 body_pose(size_t robot) const;  // T_world_body
  // T_world_cam of the left camera, optical frame: z forward, x right, y down.
  msg::Pose3 camera_pose(size_t robot) const;
  msg::Vec3 body_velocity(size_t robot) const;  // world frame, m/s
  double body_yaw_rate(size_t robot) const;     // about the world z axis, rad/s
  // T_body_cam of the left camera's optical frame: the rig's extrinsics.
  msg::Pose3 camera_mount(size_t robot) const;

  // Renders the robot's rectified stereo pair (grayscale) and, if depth_gt is given, the
  // left camera's ground-truth depth (m along the optical axis; NaN where nothing is
  // within the depth buffer's range). Sets intrinsics, baseline, pose and stamp.
  Result<void, std::string> render_stereo(size_t robot, msg::StereoFrame* stereo,
                                          msg::DepthImage* depth_gt);
  // The depth sensor of the oracle mode: ground truth with the noise model of 2.6.1
  // (as configured for the robot), NaN outside the camera range.
  void make_noisy_depth(size_t robot, msg::DepthImage& depth);
  // Renders any view, RGB rows top-down: a level free camera at `position` looking along
  // `forward` (world frame) with a vertical FOV; the ceiling hidden if asked (top views).
  Result<void, std::string> render_view(const msg::Vec3& position, const msg::Vec3& forward,
                                        double fov_v_deg, uint32_t width, uint32_t height,
                                        bool hide_ceiling, std::vector<uint8_t>* rgb,
                                        std::vector<float>* depth_m);

  // IMU of the robot now: specific force (gravity up at rest) and angular rate, body
  // frame, with the robot's noise.
  msg::Imu imu(size_t robot);
  ContactCounts contacts() const { return contacts_; }
  // Onsets since the last call, oldest first; at most kMaxPendingOnsets are kept between
  // calls (the counts above have them all).
  std::vector<ContactOnset> take_contact_onsets();
  static constexpr size_t kMaxPendingOnsets = 64;

 private:
  TeamSim() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  SceneSpec scene_;
  std::vector<RobotSpec> robots_;
  std::string mjcf_;
  ContactCounts contacts_;
};

}  // namespace scancrew::sim
