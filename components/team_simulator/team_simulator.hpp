#pragma once

// TeamSimulator: the `sim` backend. Runs the MuJoCo team simulator (sim/team_sim.hpp) on
// the launch's sim clock and stands in for every robot's hardware: for each robot of the
// launch file it publishes, in the robot's namespace,
//   stereo   (StereoFrame, camera rate)     depth    (DepthImage, noisy, thesis 2.6.1)
//   depth_gt (DepthImage, ground truth)      imu      (Imu, IMU rate)
//   pose_gt  (Odometry, ground truth, camera rate)
// and reads cmd_vel (VelocityCommand). A robot graph reads the same topic names from the
// `hardware` or `replay` backends, so it runs unchanged on any of them.
//
// Time: a timer every physics step; each tick steps MuJoCo to the clock's time, then
// renders and publishes what is due. With the step executor (lockstep), everything the
// robots do with a frame finishes before the simulation moves on: runs are deterministic.
// On the wall clock (a robot's multi-threaded graph at real-time factor 1) the physics
// starts at activation (t0) and each tick steps it to now - t0, at most max_catch_up_s at a
// time; messages are stamped t0 + the physics time they show (their capture time). A tick
// that starts more than two physics steps behind the wall is late; late ticks, ticks stopped
// at the catch-up bound and the largest lag are logged at the end and go to metrics.json.
// Not deterministic: the threads' timing decides when commands reach the physics.

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "components/team_simulator/wheel_odometry.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"
#include "sim/team_sim.hpp"

namespace scancrew::team_simulator {

class TeamSimulator final : public Component {
 public:
  // not on a robot or the station: never charged compute (StepExecutor)
  static constexpr bool kWorld = true;
  static constexpr std::string_view kDescription =
      "MuJoCo team simulator: stereo, depth, IMU and pose for every robot; reads cmd_vel (the sim "
      "backend)";
  struct Config {
    std::string scene;  // scene file, relative to the launch file (Component::input_path)
    double physics_step_s = 0.01;  // timer period; MuJoCo integrates at mjcf timestep inside it
    // a robot whose last velocity command is older than this stops (its motor controller's
    // watchdog: a robot whose process died does not drive on); 0: never
    double command_timeout_s = 0.5;
    // the first this many contact onsets are logged with time, robot, solid and place
    // (all are counted); 0: none
    int log_contacts = 20;
    uint64_t seed = 1;
    bool publish_stereo = true, publish_depth = true, publish_depth_gt = false;
    bool publish_imu = true;  // false: no imu topics (a mission without odometry reads none)
    // each ground robot's wheel odometry (wheel_odometry.hpp) on `wheel_odom`
    bool publish_wheel_odom = false;
    WheelOdometryConfig wheel;
    sim::CameraSpec ground_camera, multirotor_camera;
    sim::DepthNoiseSpec depth_noise;
    sim::ImuSpec imu;
    double ground_speed_mps = 0.5, multirotor_speed_mps = 0.6;
    double max_catch_up_s = 0.1;  // wall clock: the most physics time one tick steps (at
                                  // least one MuJoCo step)
  };
  static Config read_config(ParamReader& p);

  TeamSimulator(ComponentContext context, Config config);
  ~TeamSimulator() override;

  const sim::TeamSim* simulator() const { return sim_.get(); }
  void summarize(RunSummary& into) const override;

 private:
  struct RobotPorts {
    Publisher<msg::StereoFrame> stereo;
    Publisher<msg::DepthImage> depth, depth_gt;
    Publisher<msg::Imu> imu;
    Publisher<msg::Odometry> pose_gt, wheel_odom;
    std::optional<WheelOdometry> wheel;
    int64_t next_frame_ns = 0, next_imu_ns = 0, next_wheel_ns = 0;
    int64_t last_command_ns = -1;  // -1: none yet, or stopped by the watchdog
  };

  // Physics timing on the wall clock (WallClockSim of metrics.json).
  struct WallTiming {
    int64_t t0_ns = 0;  // the wall time of physics time 0 (activation)
    uint64_t ticks = 0, late_ticks = 0, capped_ticks = 0;
    int64_t max_lag_ns = 0;
  };

  Result<void, std::string> on_configure() override;
  void on_activate() override;
  void on_deactivate() override;
  void tick();
  // Steps the physics towards the wall time now (bounded); returns the stamp of the state
  // reached, on the wall clock.
  int64_t step_to_wall(int64_t now_ns);
  void publish_frame(size_t robot, int64_t stamp_ns);

  Config config_;
  std::unique_ptr<sim::TeamSim> sim_;
  std::vector<RobotPorts> ports_;
  uint64_t frames_ = 0, dropped_frames_ = 0;
  int contacts_logged_ = 0;
  bool wall_ = false;  // on the wall clock
  WallTiming wall_timing_;
};

}  // namespace scancrew::team_simulator
