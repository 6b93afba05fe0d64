#include "sim/team_sim.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>

#include "sim/depth_noise.hpp"
#include "sim/gl_context.hpp"
#include "sim/mesh_io.hpp"

namespace scancrew::sim {

namespace {

constexpr double kGravity = 9.81;

struct RobotIds {
  int body = -1;
  int body_geom = -1;
  int cam_left = -1, cam_right = -1;
  int qpos_x = -1, qpos_y = -1, qpos_z = -1, qpos_yaw = -1;  // qpos addresses
  int dof_x = -1, dof_y = -1, dof_z = -1, dof_yaw = -1;      // qvel addresses
  int act_x = -1, act_y = -1, act_z = -1, act_yaw = -1;
  msg::VelocityCommand command;
  std::mt19937_64 rng;
  std::vector<float> scratch;
};

msg::Quat quat_from_mat(const mjtNum mat[9]) {
  mjtNum q[4];
  mju_mat2Quat(q, mat);
  return {q[0], q[1], q[2], q[3]};
}

// writes the MJCF (also into mjcf_text) and the scene's meshes to a private temporary
// directory named for tag, and loads them into MuJoCo
Result<mjModel*, std::string> load_model(const SceneSpec& scene,
                                         const std::vector<RobotSpec>& robots, MjcfOptions mjcf,
                                         const std::string& tag, std::string& mjcf_text) {
  // MuJoCo loads from files: a private temporary directory with the MJCF and the placed,
  // textured meshes (MuJoCo 2.2 reads OBJ/STL only; load_mesh reads COLLADA and more)
  std::error_code ec;
  const auto dir = std::filesystem::temp_directory_path() / ("scancrew_scene_" + tag);
  std::filesystem::create_directories(dir, ec);
  if (ec) return make_unexpected("cannot create " + dir.string() + ": " + ec.message());
  struct RemoveDir {
    std::filesystem::path dir;
    ~RemoveDir() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  } remove_dir{dir};
  auto meshes = load_scene_meshes(scene);
  if (!meshes) return make_unexpected(meshes.error());
  for (size_t i = 0; i < meshes->size(); ++i) {
    mjcf.mesh_files.push_back((dir / (scene.meshes[i].name + ".obj")).string());
    if (auto written =
            write_textured_obj((*meshes)[i], texture_period_m(scene), mjcf.mesh_files.back());
        !written)
      return make_unexpected(written.error());
  }
  mjcf_text = build_mjcf(scene, robots, mjcf);
  const auto file = dir / "scene.xml";
  {
    std::ofstream out(file);
    out << mjcf_text;
  }
  char error[1000] = "";
  mjModel* model = mj_loadXML(file.c_str(), nullptr, error, sizeof(error));
  if (model == nullptr)
    return make_unexpected("MuJoCo cannot load the scene '" + scene.name + "': " + error);
  return model;
}

}  // namespace

struct TeamSim::Impl {
  mjModel* model = nullptr;
  mjData* data = nullptr;
  std::vector<RobotIds> ids;
  std::vector<int> geom_robot;  // robot index of a geom, -1 for the scene
  std::set<std::pair<int, int>> touching;
  double max_speed_factor = 2.0;
  // rendering
  std::unique_ptr<GlContext> gl;
  mjvScene scene{};
  mjvOption option{};
  mjrContext context{};
  bool rendering = false;
  std::vector<uint8_t> rgb;
  std::vector<float> depth_raw;

  ~Impl() {
    if (rendering) {
      gl->make_current();
      mjr_freeContext(&context);
      mjv_freeScene(&scene);
    }
    if (data) mj_deleteData(data);
    if (model) mj_deleteModel(model);
  }

  int id(mjtObj type, const std::string& name) const {
    return mj_name2id(model, type, name.c_str());
  }

  std::vector<ContactOnset> onsets;

  void count_contacts(ContactCounts& counts, const std::vector<RobotSpec>& robots) {
    std::set<std::pair<int, int>> now;
    for (int i = 0; i < data->ncon; ++i) {
      const mjContact& c = data->contact[i];
      const int r1 = geom_robot[c.geom1], r2 = geom_robot[c.geom2];
      if (r1 < 0 && r2 < 0) continue;
      const auto key = std::minmax(c.geom1, c.geom2);
      // one onset per pair: MuJoCo gives a box-box pair several contact points
      if (!now.insert(key).second || touching.count(key)) continue;
      (r1 >= 0 && r2 >= 0 ? counts.robot_robot : counts.robot_scene)++;
      if (onsets.size() >= TeamSim::kMaxPendingOnsets) continue;
      const int robot = r1 >= 0 ? r1 : r2;
      const int other_geom = r1 >= 0 ? c.geom2 : c.geom1;
      const int other_robot = r1 >= 0 ? r2 : r1;
      ContactOnset o;
      o.t_s = data->time;
      o.robot = static_cast<size_t>(robot);
      if (other_robot >= 0) {
        o.other = robots[static_cast<size_t>(other_robot)].name;
      } else {
        const char* body = mj_id2name(model, mjOBJ_BODY, model->geom_bodyid[other_geom]);
        const char* geom = mj_id2name(model, mjOBJ_GEOM, other_geom);
        o.other = geom != nullptr && *geom != '\0'   ? geom
                  : body != nullptr && *body != '\0' ? body
                                                     : "scene";
      }
      o.position = {c.pos[0], c.pos[1], c.pos[2]};
      const auto b = static_cast<size_t>(ids[static_cast<size_t>(robot)].body);
      const double* q = data->xquat + 4 * b;
      o.robot_xy_yaw = {
          data->xpos[3 * b], data->xpos[3 * b + 1],
          std::atan2(2 * (q[0] * q[3] + q[1] * q[2]), 1 - 2 * (q[2] * q[2] + q[3] * q[3]))};
      onsets.push_back(std::move(o));
    }
    touching.swap(now);
  }

  // depth buffer value -> metres along the optical axis (DEPENDENCIES.md), NaN at the far plane
  float linear_depth(float d) const {
    const double extent = model->stat.extent;
    const double znear = model->vis.map.znear * extent, zfar = model->vis.map.zfar * extent;
    if (d >= 1.0f) return std::numeric_limits<float>::quiet_NaN();
    return static_cast<float>(znear * zfar / (zfar - d * (zfar - znear)));
  }

  void render_camera(mjvCamera& camera, uint32_t w, uint32_t h) {
    gl->make_current();
    mjv_updateScene(model, data, &option, nullptr, &camera, mjCAT_ALL, &scene);
    const mjrRect viewport{0, 0, static_cast<int>(w), static_cast<int>(h)};
    mjr_render(viewport, &scene, &context);
    rgb.resize(size_t{w} * h * 3);
    depth_raw.resize(size_t{w} * h);
    mjr_readPixels(rgb.data(), depth_raw.data(), viewport, &context);
    gl->release();  // a multi-threaded executor's next tick may run on another thread
  }

  // OpenGL rows are bottom-up: row y of the image is row h-1-y of the buffer
  void to_gray(uint32_t w, uint32_t h, std::vector<uint8_t>& out) const {
    out.resize(size_t{w} * h);
    for (uint32_t y = 0; y < h; ++y) {
      const uint8_t* src = &rgb[size_t{h - 1 - y} * w * 3];
      uint8_t* dst = &out[size_t{y} * w];
      for (uint32_t x = 0; x < w; ++x)
        dst[x] = static_cast<uint8_t>((299 * src[3 * size_t{x}] + 587 * src[3 * size_t{x} + 1] +
                                       114 * src[3 * size_t{x} + 2]) /
                                      1000);
    }
  }
  void add_robots(const std::vector<RobotSpec>& robots, uint64_t seed);
  void to_depth(uint32_t w, uint32_t h, std::vector<float>& out) const {
    out.resize(size_t{w} * h);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        out[size_t{y} * w + x] = linear_depth(depth_raw[size_t{h - 1 - y} * w + x]);
  }
};

// looks up each robot's MuJoCo ids, sets its start yaw and seeds its noise generator
void TeamSim::Impl::add_robots(const std::vector<RobotSpec>& robots, uint64_t seed) {
  for (size_t i = 0; i < robots.size(); ++i) {
    const RobotSpec& r = robots[i];
    RobotIds ids;
    ids.body = id(mjOBJ_BODY, body_name(r));
    ids.body_geom = id(mjOBJ_GEOM, r.name + "_body");
    ids.cam_left = id(mjOBJ_CAMERA, camera_name(r, true));
    ids.cam_right = id(mjOBJ_CAMERA, camera_name(r, false));
    const auto joint = [&](const char* axis, int& qpos, int& dof, int& act) {
      const int j = id(mjOBJ_JOINT, joint_name(r, axis));
      if (j < 0) return;
      qpos = model->jnt_qposadr[j];
      dof = model->jnt_dofadr[j];
      act = id(mjOBJ_ACTUATOR, joint_name(r, axis) + "_vel");
    };
    joint("x", ids.qpos_x, ids.dof_x, ids.act_x);
    joint("y", ids.qpos_y, ids.dof_y, ids.act_y);
    joint("z", ids.qpos_z, ids.dof_z, ids.act_z);
    joint("yaw", ids.qpos_yaw, ids.dof_yaw, ids.act_yaw);
    geom_robot[ids.body_geom] = static_cast<int>(i);
    data->qpos[ids.qpos_yaw] = r.start_yaw_rad;
    ids.rng.seed(seed * 1'000'003u + r.id);
    this->ids.push_back(std::move(ids));
  }
}

Result<std::unique_ptr<TeamSim>, std::string> TeamSim::create(const SceneSpec& scene,
                                                              std::vector<RobotSpec> robots,
                                                              const TeamSimConfig& config) {
  auto sim = std::unique_ptr<TeamSim>(new TeamSim());
  sim->scene_ = scene;
  MjcfOptions mjcf = config.mjcf;
  for (const RobotSpec& r : robots) {
    if (auto problem = r.camera.validate(); !problem.empty())
      return make_unexpected(r.name + ": " + problem);
    mjcf.offscreen_width = std::max(mjcf.offscreen_width, r.camera.width);
    mjcf.offscreen_height = std::max(mjcf.offscreen_height, r.camera.height);
    const bool inside = r.start_x_m >= scene.min_m.x && r.start_x_m <= scene.max_m.x &&
                        r.start_y_m >= scene.min_m.y && r.start_y_m <= scene.max_m.y;
    if (!inside)
      return make_unexpected(r.name + ": start (" + std::to_string(r.start_x_m) + ", " +
                             std::to_string(r.start_y_m) + ") is outside the scene bounds");
  }
  sim->robots_ = std::move(robots);

  const auto loaded =
      load_model(scene, sim->robots_, mjcf, std::to_string(reinterpret_cast<uintptr_t>(sim.get())),
                 sim->mjcf_);
  if (!loaded) return make_unexpected(loaded.error());
  mjModel* model = *loaded;

  auto impl = std::make_unique<Impl>();
  impl->model = model;
  impl->data = mj_makeData(model);
  impl->max_speed_factor = config.max_speed_factor;
  impl->geom_robot.assign(model->ngeom, -1);
  impl->add_robots(sim->robots_, config.seed);
  mj_forward(model, impl->data);

  // a robot must not start inside an obstacle or another robot
  for (int c = 0; c < impl->data->ncon; ++c) {
    const mjContact& contact = impl->data->contact[c];
    const int r1 = impl->geom_robot[contact.geom1], r2 = impl->geom_robot[contact.geom2];
    if (r1 < 0 && r2 < 0) continue;
    const int robot = r1 >= 0 ? r1 : r2;
    const int other = r1 >= 0 ? contact.geom2 : contact.geom1;
    const char* other_name = mj_id2name(model, mjOBJ_GEOM, other);
    return make_unexpected(sim->robots_[robot].name + " starts inside '" +
                           (other_name ? other_name : "?") + "' (penetration " +
                           std::to_string(-contact.dist) + " m); move its start pose");
  }

  if (config.rendering) {
    auto gl = GlContext::create();
    if (!gl) return make_unexpected(gl.error());
    impl->gl = std::move(gl).value();
    mjv_defaultOption(&impl->option);
    mjv_defaultScene(&impl->scene);
    mjv_makeScene(model, &impl->scene, 10000);
    mjr_defaultContext(&impl->context);
    mjr_makeContext(model, &impl->context, mjFONTSCALE_100);
    mjr_setBuffer(mjFB_OFFSCREEN, &impl->context);
    if (impl->context.currentBuffer != mjFB_OFFSCREEN)
      return make_unexpected(
          std::string("no GL available: the offscreen framebuffer cannot be bound"));
    impl->rendering = true;
    impl->gl->release();  // the executor may render from another thread
  }
  sim->impl_ = std::move(impl);
  return sim;
}

TeamSim::~TeamSim() = default;

int64_t TeamSim::time_ns() const {
  return std::llround(impl_->data->time * 1e9);
}
int64_t TeamSim::timestep_ns() const {
  return std::llround(impl_->model->opt.timestep * 1e9);
}

void TeamSim::step_until(int64_t t_ns) {
  mjModel* m = impl_->model;
  mjData* d = impl_->data;
  while (time_ns() + timestep_ns() / 2 < t_ns) {
    // body-frame commands to world-frame joint velocities, from the current yaw
    for (size_t i = 0; i < robots_.size(); ++i) {
      const RobotIds& ids = impl_->ids[i];
      const RobotSpec& r = robots_[i];
      const double yaw = d->qpos[ids.qpos_yaw];
      const double c = std::cos(yaw), s = std::sin(yaw);
      const double vmax = impl_->max_speed_factor * r.nominal_speed_mps;
      // a non-finite command stops the axis (NaN passes std::clamp, and MuJoCo's state with it)
      const auto clamp = [](double v, double limit) {
        return std::isfinite(v) ? std::clamp(v, -limit, limit) : 0.0;
      };
      const double vx = clamp(ids.command.linear_mps.x, vmax);
      const double vy = r.kind == RobotKind::kGround ? 0.0 : clamp(ids.command.linear_mps.y, vmax);
      d->ctrl[ids.act_x] = c * vx - s * vy;
      d->ctrl[ids.act_y] = s * vx + c * vy;
      if (ids.act_z >= 0) d->ctrl[ids.act_z] = clamp(ids.command.linear_mps.z, vmax);
      d->ctrl[ids.act_yaw] = clamp(ids.command.yaw_rate_radps, 2.0);
    }
    mj_step(m, d);
    impl_->count_contacts(contacts_, robots_);
  }
}

std::vector<ContactOnset> TeamSim::take_contact_onsets() {
  std::vector<ContactOnset> out;
  out.swap(impl_->onsets);
  return out;
}

void TeamSim::set_velocity(size_t robot, const msg::VelocityCommand& command) {
  impl_->ids[robot].command = command;
}

msg::Pose3 TeamSim::body_pose(size_t robot) const {
  const mjData* d = impl_->data;
  const auto b = static_cast<size_t>(impl_->ids[robot].body);
  msg::Pose3 pose;
  pose.position = {d->xpos[3 * b], d->xpos[3 * b + 1], d->xpos[3 * b + 2]};
  pose.orientation = {d->xquat[4 * b], d->xquat[4 * b + 1], d->xquat[4 * b + 2],
                      d->xquat[4 * b + 3]};
  return pose;
}

msg::Vec3 TeamSim::body_velocity(size_t robot) const {
  const mjData* d = impl_->data;
  const RobotIds& ids = impl_->ids[robot];
  return {d->qvel[ids.dof_x], d->qvel[ids.dof_y], ids.dof_z >= 0 ? d->qvel[ids.dof_z] : 0.0};
}

double TeamSim::body_yaw_rate(size_t robot) const {
  return impl_->data->qvel[impl_->ids[robot].dof_yaw];
}

msg::Pose3 TeamSim::camera_pose(size_t robot) const {
  const mjData* d = impl_->data;
  const auto c = static_cast<size_t>(impl_->ids[robot].cam_left);
  // MuJoCo camera frame: x right, y up, looking along -z; optical frame: x right, y down, z forward
  mjtNum optical[9];
  const mjtNum* m = d->cam_xmat + 9 * c;
  for (int row = 0; row < 3; ++row) {
    optical[3 * row + 0] = m[3 * row + 0];
    optical[3 * row + 1] = -m[3 * row + 1];
    optical[3 * row + 2] = -m[3 * row + 2];
  }
  msg::Pose3 pose;
  pose.position = {d->cam_xpos[3 * c], d->cam_xpos[3 * c + 1], d->cam_xpos[3 * c + 2]};
  pose.orientation = quat_from_mat(optical);
  return pose;
}

msg::Pose3 TeamSim::camera_mount(size_t robot) const {
  // inverse(T_world_body) * T_world_cam; bodies only turn about z
  const msg::Pose3 body = body_pose(robot), cam = camera_pose(robot);
  mjtNum qinv[4], q[4], d[3], rotated[3];
  const mjtNum qb[4] = {body.orientation.w, body.orientation.x, body.orientation.y,
                        body.orientation.z};
  const mjtNum qc[4] = {cam.orientation.w, cam.orientation.x, cam.orientation.y, cam.orientation.z};
  mju_negQuat(qinv, qb);
  mju_mulQuat(q, qinv, qc);
  d[0] = cam.position.x - body.position.x;
  d[1] = cam.position.y - body.position.y;
  d[2] = cam.position.z - body.position.z;
  mju_rotVecQuat(rotated, d, qinv);
  return {{rotated[0], rotated[1], rotated[2]}, {q[0], q[1], q[2], q[3]}};
}

Result<void, std::string> TeamSim::render_stereo(size_t robot, msg::StereoFrame* stereo,
                                                 msg::DepthImage* depth_gt) {
  if (!impl_->rendering) return make_unexpected(std::string("rendering is off for this simulator"));
  const RobotSpec& r = robots_[robot];
  const RobotIds& ids = impl_->ids[robot];
  const uint32_t w = r.camera.width, h = r.camera.height;
  const double f = r.camera.fx_px();
  const msg::CameraIntrinsics intrinsics{w, h, f, f, 0.5 * w - 0.5, 0.5 * h - 0.5};
  mjvCamera camera;
  mjv_defaultCamera(&camera);
  camera.type = mjCAMERA_FIXED;
  camera.fixedcamid = ids.cam_left;
  impl_->render_camera(camera, w, h);
  if (stereo != nullptr) {
    impl_->to_gray(w, h, stereo->left);
    stereo->T_body_cam = camera_mount(robot);
  }
  if (depth_gt != nullptr) {
    impl_->to_depth(w, h, depth_gt->depth_m);
    depth_gt->intrinsics = intrinsics;
    depth_gt->T_world_cam = camera_pose(robot);
    depth_gt->min_range_m = 0;
    depth_gt->max_range_m = std::numeric_limits<double>::infinity();
    depth_gt->header.stamp_ns = time_ns();
  }
  if (stereo != nullptr) {
    camera.fixedcamid = ids.cam_right;
    impl_->render_camera(camera, w, h);
    impl_->to_gray(w, h, stereo->right);
    stereo->intrinsics = intrinsics;
    stereo->baseline_m = r.camera.baseline_m;
    stereo->header.stamp_ns = time_ns();
  }
  return {};
}

void TeamSim::make_noisy_depth(size_t robot, msg::DepthImage& depth) {
  const RobotSpec& r = robots_[robot];
  DepthNoiseParams p;
  p.add_noise = r.depth_noise.enabled;
  p.smoothing = r.depth_noise.enabled && r.depth_noise.smoothing;
  p.disparity_error_px = r.depth_noise.disparity_error_px;
  p.fx_px = r.camera.fx_px();
  p.baseline_m = r.camera.baseline_m;
  p.min_range_m = r.camera.min_range_m;
  p.max_range_m = r.camera.max_range_m;
  apply_depth_noise(depth.depth_m, depth.intrinsics.width, depth.intrinsics.height, p,
                    impl_->ids[robot].rng, impl_->ids[robot].scratch);
  depth.min_range_m = r.camera.min_range_m;
  depth.max_range_m = r.camera.max_range_m;
}

Result<void, std::string> TeamSim::render_view(const msg::Vec3& position, const msg::Vec3& forward,
                                               double fov_v_deg, uint32_t width, uint32_t height,
                                               bool hide_ceiling, std::vector<uint8_t>* rgb,
                                               std::vector<float>* depth_m) {
  if (!impl_->rendering) return make_unexpected(std::string("rendering is off for this simulator"));
  if (width > static_cast<uint32_t>(impl_->model->vis.global.offwidth) ||
      height > static_cast<uint32_t>(impl_->model->vis.global.offheight))
    return make_unexpected("view " + std::to_string(width) + "x" + std::to_string(height) +
                           " exceeds the offscreen buffer " +
                           std::to_string(impl_->model->vis.global.offwidth) + "x" +
                           std::to_string(impl_->model->vis.global.offheight));
  const double norm =
      std::sqrt(forward.x * forward.x + forward.y * forward.y + forward.z * forward.z);
  if (!(norm > 0)) return make_unexpected(std::string("render_view: forward must not be zero"));
  const double f[3] = {forward.x / norm, forward.y / norm, forward.z / norm};
  // a free camera orbits `lookat` at `distance`: put lookat 1 m ahead of the position
  mjvCamera camera;
  mjv_defaultCamera(&camera);
  camera.type = mjCAMERA_FREE;
  camera.distance = 1.0;
  camera.lookat[0] = position.x + f[0];
  camera.lookat[1] = position.y + f[1];
  camera.lookat[2] = position.z + f[2];
  camera.azimuth = std::atan2(f[1], f[0]) * 180.0 / M_PI;
  camera.elevation = std::asin(std::clamp(f[2], -1.0, 1.0)) * 180.0 / M_PI;
  const float saved_fovy = impl_->model->vis.global.fovy;
  impl_->model->vis.global.fovy = static_cast<float>(fov_v_deg);
  impl_->option.geomgroup[1] = hide_ceiling ? 0 : 1;
  impl_->render_camera(camera, width, height);
  impl_->option.geomgroup[1] = 1;
  impl_->model->vis.global.fovy = saved_fovy;
  if (rgb != nullptr) {
    rgb->resize(size_t{width} * height * 3);
    for (uint32_t y = 0; y < height; ++y)
      std::memcpy(&(*rgb)[size_t{y} * width * 3], &impl_->rgb[size_t{height - 1 - y} * width * 3],
                  size_t{width} * 3);
  }
  if (depth_m != nullptr) impl_->to_depth(width, height, *depth_m);
  return {};
}

msg::Imu TeamSim::imu(size_t robot) {
  const mjData* d = impl_->data;
  RobotIds& ids = impl_->ids[robot];
  const RobotSpec& r = robots_[robot];
  const double yaw = d->qpos[ids.qpos_yaw];
  // specific force = acceleration - gravity, in the body frame (yaw only: no roll or pitch)
  const double ax = d->qacc[ids.dof_x], ay = d->qacc[ids.dof_y];
  const double az = (ids.dof_z >= 0 ? d->qacc[ids.dof_z] : 0.0) + kGravity;
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::normal_distribution<double> unit(0.0, 1.0);
  msg::Imu imu;
  imu.linear_acceleration_mps2 = {c * ax + s * ay + unit(ids.rng) * r.imu.accel_noise_mps2,
                                  -s * ax + c * ay + unit(ids.rng) * r.imu.accel_noise_mps2,
                                  az + unit(ids.rng) * r.imu.accel_noise_mps2};
  imu.angular_velocity_radps = {unit(ids.rng) * r.imu.gyro_noise_radps,
                                unit(ids.rng) * r.imu.gyro_noise_radps,
                                d->qvel[ids.dof_yaw] + unit(ids.rng) * r.imu.gyro_noise_radps};
  imu.header.stamp_ns = time_ns();
  return imu;
}

}  // namespace scancrew::sim
