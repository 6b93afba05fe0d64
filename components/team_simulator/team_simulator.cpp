#include "components/team_simulator/team_simulator.hpp"

#include <algorithm>
#include <cmath>

#include "executors/log.hpp"
#include "executors/registry.hpp"

namespace scancrew::team_simulator {

namespace {

void read_camera(ParamReader& p, const std::string& prefix, sim::CameraSpec& c) {
  p.optional(prefix + "width", c.width, {16, 8192}).doc("camera image width (px)");
  p.optional(prefix + "height", c.height, {16, 8192})
      .doc("camera image height (px; square pixels: must match the FOVs' aspect)");
  p.optional(prefix + "fov_h_deg", c.fov_h_deg, {10, 170})
      .doc("camera horizontal field of view (degrees)");
  p.optional(prefix + "fov_v_deg", c.fov_v_deg, {10, 170})
      .doc("camera vertical field of view (degrees)");
  p.optional(prefix + "baseline_m", c.baseline_m, {0, 2})
      .doc("stereo baseline (m; 0.26 ground robots, 0.11 multirotors)");
  p.optional(prefix + "rate_hz", c.rate_hz, {0.01, 1000}).doc("camera frame rate (Hz)");
  p.optional(prefix + "min_range_m", c.min_range_m, {0.01, 100})
      .doc("depth camera range: nearest (m)");
  p.optional(prefix + "max_range_m", c.max_range_m, {0.02, 1000})
      .doc("depth camera range: farthest (m)");
  p.optional(prefix + "mount_forward_m", c.mount_forward_m, {0, 5})
      .doc("left camera centre ahead of the body centre (m)");
  p.optional(prefix + "mount_up_m", c.mount_up_m, {-5, 5})
      .doc(
          "left camera centre height (m; ground robot: above the floor; multirotor: above the body "
          "centre)");
  if (auto problem = c.validate(); !problem.empty()) p.report(prefix + "width", problem);
}

int64_t period_ns(double rate_hz) {
  return static_cast<int64_t>(std::llround(1e9 / rate_hz));
}

}  // namespace

TeamSimulator::Config TeamSimulator::read_config(ParamReader& p) {
  Config c;
  c.ground_camera = sim::default_camera(robot::RobotKind::kGround);
  c.multirotor_camera = sim::default_camera(robot::RobotKind::kMultirotor);
  p.required("scene", c.scene).doc("scene file (launch_cfg/scenes/*.yaml)");
  p.optional("physics_step_s", c.physics_step_s, {1e-4, 1})
      .doc("timer period; MuJoCo integrates at the MJCF timestep inside it (s)");
  p.optional("command_timeout_s", c.command_timeout_s, {0, 3600})
      .doc("a robot whose last velocity command is older than this stops (s; 0: never)");
  p.optional("log_contacts", c.log_contacts, {0, 100000})
      .doc("the first this many contact onsets are logged (all are counted; 0: none)");
  p.optional("seed", c.seed).doc("random seed of the sensor noise");
  p.optional("publish_stereo", c.publish_stereo).doc("publish each robot's stereo pair (stereo)");
  p.optional("publish_depth", c.publish_depth).doc("publish each robot's noisy depth (depth)");
  p.optional("publish_depth_gt", c.publish_depth_gt)
      .doc("publish each robot's ground-truth depth (depth_gt)");
  p.optional("publish_imu", c.publish_imu)
      .doc("publish each robot's IMU (false: a mission without odometry reads none)");
  read_camera(p, "ground_camera_", c.ground_camera);
  read_camera(p, "multirotor_camera_", c.multirotor_camera);
  p.optional("depth_noise", c.depth_noise.enabled)
      .doc("add disparity noise to the depth (thesis 2.6.1)");
  p.optional("disparity_error_px", c.depth_noise.disparity_error_px, {0, 10})
      .doc("|e_d|, the disparity error (px; tables 2.1, 3.1, 4.1)");
  p.optional("depth_smoothing", c.depth_noise.smoothing)
      .doc("3x3 Gaussian after the noise (2.6.1)");
  p.optional("imu_rate_hz", c.imu.rate_hz, {0.1, 2000}).doc("IMU rate (Hz)");
  p.optional("imu_accel_noise_mps2", c.imu.accel_noise_mps2, {0, 10})
      .doc("accelerometer white noise, standard deviation per sample (m/s²)");
  p.optional("imu_gyro_noise_radps", c.imu.gyro_noise_radps, {0, 10})
      .doc("gyro white noise, standard deviation per sample (rad/s)");
  p.optional("publish_wheel_odom", c.publish_wheel_odom)
      .doc("publish each ground robot's wheel odometry (wheel_odom)");
  p.optional("wheel_odom_rate_hz", c.wheel.rate_hz, {0.1, 2000}).doc("wheel odometry rate (Hz)");
  p.optional("wheel_scale_sigma", c.wheel.scale_sigma, {0, 0.5})
      .doc("standard deviation of the per-robot wheel scale error");
  p.optional("wheel_speed_noise_mps", c.wheel.speed_noise_mps, {0, 10})
      .doc("wheel odometry speed white noise per sample, each axis (m/s)");
  p.optional("wheel_yaw_rate_noise_radps", c.wheel.yaw_rate_noise_radps, {0, 10})
      .doc("wheel odometry yaw rate white noise per sample (rad/s)");
  p.optional("ground_speed_mps", c.ground_speed_mps, {0.01, 10})
      .doc("ground robots' nominal speed (m/s; table 5.3)");
  p.optional("multirotor_speed_mps", c.multirotor_speed_mps, {0.01, 20})
      .doc("multirotors' nominal speed (m/s; 2.6.1)");
  p.optional("max_catch_up_s", c.max_catch_up_s, {1e-3, 10})
      .doc("wall clock: the most physics time one tick steps (s)");
  return c;
}

TeamSimulator::TeamSimulator(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

TeamSimulator::~TeamSimulator() = default;

Result<void, std::string> TeamSimulator::on_configure() {
  wall_ = clock().type() == ClockType::kWall;
  config_.scene = input_path("scene", config_.scene);
  if (team().empty() || team().front().ns.empty())
    return make_unexpected(
        std::string("the team simulator needs a robots: section (id, namespace, kind, start)"));
  auto scene = sim::load_scene(config_.scene);
  if (!scene) {
    std::string all;
    for (const auto& e : scene.error()) all += (all.empty() ? "" : "; ") + e;
    return make_unexpected("scene: " + all);
  }
  std::vector<sim::RobotSpec> robots;
  for (const TeamMember& m : team()) {
    sim::RobotSpec r;
    r.id = m.id;
    r.name = m.ns;
    r.kind = m.kind;
    r.start_x_m = m.start_x_m;
    r.start_y_m = m.start_y_m;
    r.start_z_m = m.start_z_m;
    r.start_yaw_rad = m.start_yaw_rad;
    const bool ground = r.kind == robot::RobotKind::kGround;
    r.camera = ground ? config_.ground_camera : config_.multirotor_camera;
    r.nominal_speed_mps = ground ? config_.ground_speed_mps : config_.multirotor_speed_mps;
    r.imu = config_.imu;
    r.depth_noise = config_.depth_noise;
    robots.push_back(r);
  }
  sim::TeamSimConfig sim_config;
  sim_config.seed = config_.seed;
  sim_config.rendering =
      config_.publish_stereo || config_.publish_depth || config_.publish_depth_gt;
  auto made = sim::TeamSim::create(*scene, std::move(robots), sim_config);
  if (!made) return make_unexpected(made.error());
  sim_ = std::move(made).value();

  ports_.resize(sim_->robot_count());
  for (size_t i = 0; i < sim_->robot_count(); ++i) {
    const std::string ns = sim_->robot(i).name + "/";
    RobotPorts& p = ports_[i];
    if (config_.publish_stereo)
      p.stereo = create_publisher<msg::StereoFrame>(ns + "stereo", {.pool_size = 4});
    if (config_.publish_depth)
      p.depth = create_publisher<msg::DepthImage>(ns + "depth", {.pool_size = 4});
    if (config_.publish_depth_gt)
      p.depth_gt = create_publisher<msg::DepthImage>(ns + "depth_gt", {.pool_size = 4});
    if (config_.publish_imu) p.imu = create_publisher<msg::Imu>(ns + "imu", {.pool_size = 16});
    p.pose_gt = create_publisher<msg::Odometry>(ns + "pose_gt", {.pool_size = 8});
    if (config_.publish_wheel_odom && sim_->robot(i).kind == robot::RobotKind::kGround) {
      p.wheel_odom = create_publisher<msg::Odometry>(ns + "wheel_odom", {.pool_size = 16});
      p.wheel_odom.set_robot_id(sim_->robot(i).id);
      // a stream of its own per robot: the other noise is the same with or without it
      p.wheel.emplace(config_.wheel, config_.seed * 7'919u + sim_->robot(i).id + 0x5eedu,
                      sim_->body_pose(i));
    }
    // the simulator publishes on behalf of each robot: its messages carry the robot's id
    const uint32_t id = sim_->robot(i).id;
    if (p.stereo.valid()) p.stereo.set_robot_id(id);
    for (auto* pub : {&p.depth, &p.depth_gt})
      if (pub->valid()) pub->set_robot_id(id);
    if (p.imu.valid()) p.imu.set_robot_id(id);
    p.pose_gt.set_robot_id(id);
    create_subscription<msg::VelocityCommand>(ns + "cmd_vel", {.depth = 1},
                                              [this, i](Sample<msg::VelocityCommand>&& c) {
                                                sim_->set_velocity(i, *c);
                                                ports_[i].last_command_ns = clock().now_ns();
                                              });
  }
  create_timer(std::chrono::nanoseconds(period_ns(1.0 / config_.physics_step_s)),
               [this] { tick(); });
  return {};
}

void TeamSimulator::tick() {
  const int64_t now = clock().now_ns();
  const auto timeout_ns = static_cast<int64_t>(config_.command_timeout_s * 1e9);
  if (timeout_ns > 0)
    for (size_t i = 0; i < ports_.size(); ++i)
      if (ports_[i].last_command_ns >= 0 && now - ports_[i].last_command_ns > timeout_ns) {
        sim_->set_velocity(i, msg::VelocityCommand{});
        ports_[i].last_command_ns = -1;
        SCANCREW_LOG_WARN("%s: robot %u: no velocity command for %.2f s: stopped (watchdog)",
                          qualified_name().c_str(), sim_->robot(i).id, config_.command_timeout_s);
      }
  // the time the physics shows, on the launch's clock: the sensors' capture stamp
  int64_t stamp = now;
  if (wall_)
    stamp = step_to_wall(now);
  else
    sim_->step_until(now);
  for (const sim::ContactOnset& o : sim_->take_contact_onsets()) {
    if (contacts_logged_ >= config_.log_contacts) break;
    ++contacts_logged_;
    SCANCREW_LOG_WARN(
        "%s: contact at %.2f s: robot %u (at %.2f, %.2f, yaw %.0f deg) touches %s at (%.2f, "
        "%.2f, %.2f)%s",
        qualified_name().c_str(), o.t_s, sim_->robot(o.robot).id, o.robot_xy_yaw.x,
        o.robot_xy_yaw.y, o.robot_xy_yaw.z * 180.0 / M_PI, o.other.c_str(), o.position.x,
        o.position.y, o.position.z,
        contacts_logged_ == config_.log_contacts ? " (further contacts are counted only)" : "");
  }
  for (size_t i = 0; i < ports_.size(); ++i) {
    RobotPorts& p = ports_[i];
    const sim::RobotSpec& robot = sim_->robot(i);
    // on the wall clock the schedule keeps its rate whatever the ticks' jitter (a period
    // missed whole is skipped)
    const auto next = [&](int64_t due, double rate_hz) {
      const int64_t period = period_ns(rate_hz);
      return wall_ && due + period > stamp ? due + period : stamp + period;
    };
    if (stamp >= p.next_imu_ns) {
      p.next_imu_ns = next(p.next_imu_ns, robot.imu.rate_hz);
      // drawn even when not published: the IMU noise and the depth noise share the robot's
      // generator, so the depth is the same with or without the imu topic
      const msg::Imu imu = sim_->imu(i);
      if (p.imu.valid())
        if (auto loan = p.imu.loan()) {
          **loan = imu;
          (**loan).header.stamp_ns = stamp;
          (void)p.imu.publish(std::move(*loan));
        }
    }
    if (p.wheel && stamp >= p.next_wheel_ns) {
      p.next_wheel_ns = next(p.next_wheel_ns, config_.wheel.rate_hz);
      const double yaw = heading_of(sim_->body_pose(i).orientation);
      // measured whether or not a buffer is free: the dead reckoning goes on
      const msg::Odometry reading =
          p.wheel->measure(stamp, sim_->body_velocity(i), yaw, sim_->body_yaw_rate(i));
      if (auto loan = p.wheel_odom.loan()) {
        **loan = reading;
        (void)p.wheel_odom.publish(std::move(*loan));
      }
    }
    if (stamp >= p.next_frame_ns) {
      p.next_frame_ns = next(p.next_frame_ns, robot.camera.rate_hz);
      publish_frame(i, stamp);
    }
  }
}

int64_t TeamSimulator::step_to_wall(int64_t now_ns) {
  WallTiming& w = wall_timing_;
  const int64_t due = now_ns - w.t0_ns;
  const auto step_ns = static_cast<int64_t>(std::llround(config_.physics_step_s * 1e9));
  ++w.ticks;
  if (due - sim_->time_ns() > 2 * step_ns) ++w.late_ticks;
  // at least one MuJoCo step, or the physics could never move
  const int64_t cap_ns = std::max(static_cast<int64_t>(std::llround(config_.max_catch_up_s * 1e9)),
                                  sim_->timestep_ns());
  const int64_t target = std::min(due, sim_->time_ns() + cap_ns);
  if (target < due) ++w.capped_ticks;
  sim_->step_until(target);
  w.max_lag_ns = std::max(w.max_lag_ns, due - sim_->time_ns());
  return w.t0_ns + sim_->time_ns();
}

void TeamSimulator::publish_frame(size_t i, int64_t stamp_ns) {
  RobotPorts& p = ports_[i];
  ++frames_;
  // ground-truth pose at capture time
  if (auto loan = p.pose_gt.loan()) {
    msg::Odometry& odom = **loan;
    odom.header.stamp_ns = stamp_ns;
    odom.T_world_body = sim_->body_pose(i);
    odom.linear_velocity_mps = sim_->body_velocity(i);
    odom.angular_velocity_radps = {0, 0, sim_->body_yaw_rate(i)};
    odom.tracking_quality = 1.0;
    (void)p.pose_gt.publish(std::move(*loan));
  }
  if (!p.stereo.valid() && !p.depth.valid() && !p.depth_gt.valid()) return;
  // loan everything first: a frame whose buffers cannot be had is dropped whole, and counted
  Loan<msg::StereoFrame> stereo;
  Loan<msg::DepthImage> depth, depth_gt;
  bool ok = true;
  const auto take = [&ok](auto& publisher, auto& out) {
    if (!publisher.valid()) return;
    auto loan = publisher.loan();
    if (loan)
      out = std::move(loan).value();
    else
      ok = false;
  };
  take(p.stereo, stereo);
  take(p.depth, depth);
  take(p.depth_gt, depth_gt);
  if (!ok) {
    ++dropped_frames_;
    return;
  }
  // ground truth goes into the noisy message's buffer first (one render for both)
  msg::DepthImage* gt_target = depth.valid() ? &*depth : (depth_gt.valid() ? &*depth_gt : nullptr);
  if (auto r = sim_->render_stereo(i, stereo.valid() ? &*stereo : nullptr, gt_target); !r) {
    SCANCREW_LOG_ERROR("%s: %s", qualified_name().c_str(), r.error().c_str());
    ++dropped_frames_;
    return;
  }
  if (depth.valid() && depth_gt.valid()) {
    depth_gt->intrinsics = depth->intrinsics;
    depth_gt->T_world_cam = depth->T_world_cam;
    depth_gt->min_range_m = depth->min_range_m;
    depth_gt->max_range_m = depth->max_range_m;
    depth_gt->depth_m.assign(depth->depth_m.begin(),
                             depth->depth_m.end());  // capacity kept: no allocation
  }
  if (depth.valid()) sim_->make_noisy_depth(i, *depth);
  if (stereo.valid()) {
    stereo->header.stamp_ns = stamp_ns;
    (void)p.stereo.publish(std::move(stereo));
  }
  if (depth.valid()) {
    depth->header.stamp_ns = stamp_ns;
    (void)p.depth.publish(std::move(depth));
  }
  if (depth_gt.valid()) {
    depth_gt->header.stamp_ns = stamp_ns;
    (void)p.depth_gt.publish(std::move(depth_gt));
  }
}

void TeamSimulator::on_activate() {
  if (wall_) wall_timing_ = {.t0_ns = clock().now_ns()};
}

void TeamSimulator::on_deactivate() {
  if (!sim_) return;
  if (wall_) {
    const WallTiming& w = wall_timing_;
    SCANCREW_LOG_INFO(
        "%s: wall clock: %llu ticks, %llu late (more than two physics steps behind), %llu at "
        "the catch-up bound; the physics lagged the wall by %.3f s at most",
        qualified_name().c_str(), static_cast<unsigned long long>(w.ticks),
        static_cast<unsigned long long>(w.late_ticks),
        static_cast<unsigned long long>(w.capped_ticks), static_cast<double>(w.max_lag_ns) * 1e-9);
  }
  const sim::ContactCounts c = sim_->contacts();
  SCANCREW_LOG_INFO(
      "%s: %.1f s simulated, %llu frames, %llu dropped (no free buffer), contacts robot-scene "
      "%llu, "
      "robot-robot %llu",
      qualified_name().c_str(), sim_->time_ns() * 1e-9, static_cast<unsigned long long>(frames_),
      static_cast<unsigned long long>(dropped_frames_),
      static_cast<unsigned long long>(c.robot_scene),
      static_cast<unsigned long long>(c.robot_robot));
}

void TeamSimulator::summarize(RunSummary& into) const {
  if (!sim_) return;
  into.contacts.robot_scene += sim_->contacts().robot_scene;
  into.contacts.robot_robot += sim_->contacts().robot_robot;
  if (!wall_) return;
  const WallTiming& w = wall_timing_;
  into.wall_clock_sim =
      RunSummary::WallClockSim{.simulated_s = static_cast<double>(sim_->time_ns()) * 1e-9,
                               .ticks = w.ticks,
                               .late_ticks = w.late_ticks,
                               .capped_ticks = w.capped_ticks,
                               .max_lag_s = static_cast<double>(w.max_lag_ns) * 1e-9};
}

SCANCREW_REGISTER_COMPONENT(TeamSimulator, "team_simulator")

}  // namespace scancrew::team_simulator
