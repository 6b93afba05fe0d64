#include "sim/mjcf_builder.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/robot/body_model.hpp"

namespace scancrew::sim {

namespace {

std::string rgb(const Rgb& c) {
  std::ostringstream s;
  s << c.r << " " << c.g << " " << c.b;
  return s.str();
}

std::string vec(double x, double y, double z) {
  std::ostringstream s;
  s.precision(10);
  s << x << " " << y << " " << z;
  return s.str();
}

// contype/conaffinity: scene solids are 1, robots 2 (collide with scene and each other);
// the floor and meshes collide with nothing (see MeshSpec; ground robots ride above the floor).
constexpr const char* kSolid = R"( contype="1" conaffinity="3")";
constexpr const char* kNoCollision = R"( contype="0" conaffinity="0")";
constexpr double kRobotMassKg = 10.0;
constexpr double kRobotInertia = 1.0;  // kg m^2 about every axis (only yaw turns)
// the dot texture's mean grey: half its texels 0.35, half 0.95 (random="0.5" below)
constexpr double kDotsMeanGrey = 0.65;

Rgb plain_color(const Rgb& c) {
  return {kDotsMeanGrey * c.r, kDotsMeanGrey * c.g, kDotsMeanGrey * c.b};
}

}  // namespace

std::string joint_name(const RobotSpec& robot, const char* axis) {
  return robot.name + "_" + axis;
}
std::string camera_name(const RobotSpec& robot, bool left) {
  return robot.name + (left ? "_left" : "_right");
}
std::string body_name(const RobotSpec& robot) {
  return robot.name;
}

double texture_period_m(const SceneSpec& scene) {
  return 1024 * scene.dot_size_m;
}

double camera_height_m(const RobotSpec& robot) {
  return robot.camera.mount_up_m;
}

namespace {

// the scene's materials and meshes (inside <asset>)
void write_materials(std::ostream& x, const SceneSpec& scene, const MjcfOptions& o,
                     double texrepeat) {
  const auto material = [&](const std::string& name, const Rgb& c,
                            SurfaceTexture texture = SurfaceTexture::kDots) {
    x << "    <material name=\"" << name << "\"";
    // plain: the colour alone (the texture's mean grey times the colour, so a plain face is
    // about as bright as a dotted one)
    if (texture == SurfaceTexture::kPlain)
      x << " rgba=\"" << rgb(plain_color(c)) << " 1\"";
    else
      x << " texture=\"dots\" texuniform=\"true\" texrepeat=\"" << texrepeat << " " << texrepeat
        << "\" rgba=\"" << rgb(c) << " 1\"";
    x << " specular=\"0\" shininess=\"0\"/>\n";
  };
  material("floor_mat", {0.8, 0.8, 0.75});
  material("wall_mat", {0.75, 0.8, 0.85}, scene.walls_texture);
  for (const auto& b : scene.boxes) material("obj_" + b.name, b.color, b.texture);
  for (const auto& c : scene.cylinders) material("obj_" + c.name, c.color, c.texture);
  // meshes carry their own texture coordinates (one repeat per texture period)
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    const MeshSpec& m = scene.meshes[i];
    x << "    <material name=\"obj_" << m.name << "\" texture=\"dots\" texrepeat=\"1 1\" rgba=\""
      << rgb(m.color) << " 1\" specular=\"0\" shininess=\"0\"/>\n"
      << "    <mesh name=\"" << m.name << "_mesh\" file=\"" << o.mesh_files.at(i) << "\"/>\n";
  }
}

// the floor, ceiling, walls and the scene's objects (inside <worldbody>)
void write_scene_geoms(std::ostream& x, const SceneSpec& scene, double sx, double sy, double cx,
                       double cy) {
  // floor, ceiling, walls
  x << "    <geom name=\"floor\" type=\"plane\" pos=\"" << vec(cx, cy, 0) << "\" size=\""
    << 0.5 * sx + 1 << " " << 0.5 * sy + 1 << " 0.1\" material=\"floor_mat\"" << kNoCollision
    << "/>\n";
  if (scene.ceiling)
    x << "    <geom name=\"ceiling\" type=\"box\" pos=\"" << vec(cx, cy, scene.max_m.z + 0.05)
      << "\" size=\"" << vec(0.5 * sx + 0.2, 0.5 * sy + 0.2, 0.05)
      << "\" material=\"wall_mat\" group=\"1\"" << kSolid << "/>\n";
  if (scene.wall_height_m > 0) {
    const double t = scene.wall_thickness_m, h = scene.wall_height_m;
    struct Wall {
      const char* name;
      double x, y, hx, hy;
    };
    const Wall walls[] = {
        {"wall_north", cx, scene.max_m.y + 0.5 * t, 0.5 * sx + t, 0.5 * t},
        {"wall_south", cx, scene.min_m.y - 0.5 * t, 0.5 * sx + t, 0.5 * t},
        {"wall_east", scene.max_m.x + 0.5 * t, cy, 0.5 * t, 0.5 * sy},
        {"wall_west", scene.min_m.x - 0.5 * t, cy, 0.5 * t, 0.5 * sy},
    };
    for (const Wall& w : walls)
      x << "    <geom name=\"" << w.name << "\" type=\"box\" pos=\"" << vec(w.x, w.y, 0.5 * h)
        << "\" size=\"" << vec(w.hx, w.hy, 0.5 * h) << "\" material=\"wall_mat\"" << kSolid
        << "/>\n";
  }
  for (const auto& b : scene.boxes)
    x << "    <geom name=\"" << b.name << "\" type=\"box\" pos=\""
      << vec(b.center_m.x, b.center_m.y, b.center_m.z) << "\" euler=\"0 0 " << b.yaw_rad
      << "\" size=\"" << vec(0.5 * b.size_m.x, 0.5 * b.size_m.y, 0.5 * b.size_m.z)
      << "\" material=\"obj_" << b.name << "\"" << kSolid << "/>\n";
  for (const auto& c : scene.cylinders)
    x << "    <geom name=\"" << c.name << "\" type=\"cylinder\" pos=\""
      << vec(c.center_m.x, c.center_m.y, c.center_m.z) << "\" size=\"" << c.radius_m << " "
      << 0.5 * c.height_m << "\" material=\"obj_" << c.name << "\"" << kSolid << "/>\n";
  for (const auto& m : scene.meshes)
    x << "    <geom name=\"" << m.name << "\" type=\"mesh\" mesh=\"" << m.name
      << "_mesh\" material=\"obj_" << m.name << "\"" << kNoCollision << "/>\n";
}

// one robot's body: its joints, inertia, box and stereo cameras
void write_robot(std::ostream& x, const RobotSpec& r) {
  const Eigen::Vector3d b = robot::BodyModel::of(r.kind).frame_half_m;
  const bool ground = r.kind == RobotKind::kGround;
  // a ground robot's body frame is on the floor under its centre; a multirotor's at its centre
  const double z0 = ground ? 0.0 : r.start_z_m;
  const double geom_z = ground ? b.z() + 0.02 : 0.0;
  x << "    <body name=\"" << body_name(r) << "\" pos=\"" << vec(r.start_x_m, r.start_y_m, z0)
    << "\">\n"
    << "      <joint name=\"" << joint_name(r, "x")
    << "\" type=\"slide\" axis=\"1 0 0\" damping=\"0\"/>\n"
    << "      <joint name=\"" << joint_name(r, "y")
    << "\" type=\"slide\" axis=\"0 1 0\" damping=\"0\"/>\n";
  if (!ground)
    x << "      <joint name=\"" << joint_name(r, "z") << "\" type=\"slide\" axis=\"0 0 1\"/>\n";
  x << "      <joint name=\"" << joint_name(r, "yaw")
    << "\" type=\"hinge\" axis=\"0 0 1\" ref=\"0\"/>\n"
    << "      <inertial pos=\"0 0 0\" mass=\"" << kRobotMassKg << "\" diaginertia=\""
    << vec(kRobotInertia, kRobotInertia, kRobotInertia) << "\"/>\n"
    << "      <geom name=\"" << r.name << "_body\" type=\"box\" pos=\"" << vec(0, 0, geom_z)
    << "\" size=\"" << vec(b.x(), b.y(), b.z()) << "\" material=\"robot_mat\""
    << " contype=\"2\" conaffinity=\"3\"/>\n";
  // cameras look along their -z; x right, y up: xyaxes "0 -1 0 0 0 1" looks along body +x
  const double fov_v =
      r.camera.fov_v_deg;  // MJCF fovy is in degrees whatever the compiler's angle unit
  const double cam_z = camera_height_m(r);
  const double cam_x = std::max(r.camera.mount_forward_m, b.x() + 0.01);
  x << "      <camera name=\"" << camera_name(r, true) << "\" pos=\"" << vec(cam_x, 0, cam_z)
    << "\" xyaxes=\"0 -1 0 0 0 1\" fovy=\"" << fov_v << "\"/>\n"
    << "      <camera name=\"" << camera_name(r, false) << "\" pos=\""
    << vec(cam_x, -r.camera.baseline_m, cam_z) << "\" xyaxes=\"0 -1 0 0 0 1\" fovy=\"" << fov_v
    << "\"/>\n"
    << "    </body>\n";
}

// each robot's velocity actuators, one per joint
void write_actuators(std::ostream& x, const std::vector<RobotSpec>& robots, const MjcfOptions& o) {
  for (const RobotSpec& r : robots) {
    // first-order tracking: each step removes velocity_response of the velocity error
    const double kv = o.velocity_response * kRobotMassKg / o.timestep_s;
    const double kv_yaw = o.velocity_response * kRobotInertia / o.timestep_s;
    std::vector<std::string> axes = {"x", "y", "yaw"};
    if (r.kind == RobotKind::kMultirotor) axes.insert(axes.begin() + 2, "z");
    for (const auto& a : axes)
      x << "    <velocity name=\"" << joint_name(r, a.c_str()) << "_vel\" joint=\""
        << joint_name(r, a.c_str()) << "\" kv=\"" << (a == "yaw" ? kv_yaw : kv) << "\"/>\n";
  }
}

}  // namespace

std::string build_mjcf(const SceneSpec& scene, const std::vector<RobotSpec>& robots,
                       const MjcfOptions& o) {
  const double sx = scene.max_m.x - scene.min_m.x, sy = scene.max_m.y - scene.min_m.y,
               sz = scene.max_m.z - scene.min_m.z;
  const double cx = 0.5 * (scene.min_m.x + scene.max_m.x),
               cy = 0.5 * (scene.min_m.y + scene.max_m.y);
  const double extent = std::sqrt(sx * sx + sy * sy + sz * sz);
  // depth buffer range: 2 cm to 4x the scene diagonal (relative to the extent, as MuJoCo wants)
  const double znear = 0.02 / extent, zfar = 4.0;
  // random dots: one texel per dot, a 1024-texel texture repeated every 1024 dots
  const double texrepeat = 1.0 / texture_period_m(scene);

  std::ostringstream x;
  x.precision(10);
  x << "<mujoco model=\"" << scene.name << "\">\n"
    << "  <compiler angle=\"radian\"/>\n"
    << "  <option timestep=\"" << o.timestep_s << "\" gravity=\"0 0 0\" integrator=\"Euler\"/>\n"
    << "  <statistic extent=\"" << extent << "\" center=\"" << vec(cx, cy, 0.5 * sz) << "\"/>\n"
    << "  <visual>\n"
    << "    <global offwidth=\"" << o.offscreen_width << "\" offheight=\"" << o.offscreen_height
    << "\"/>\n"
    << "    <quality offsamples=\"0\" shadowsize=\"0\"/>\n"
    << "    <map znear=\"" << znear << "\" zfar=\"" << zfar << "\"/>\n"
    << "    <headlight ambient=\"0.45 0.45 0.45\" diffuse=\"0.5 0.5 0.5\" specular=\"0 0 0\"/>\n"
    << "  </visual>\n"
    << "  <asset>\n"
    << "    <texture name=\"dots\" type=\"2d\" builtin=\"flat\" width=\"1024\" height=\"1024\" "
       "rgb1=\"0.35 0.35 0.35\""
    << " mark=\"random\" random=\"0.5\" markrgb=\"0.95 0.95 0.95\"/>\n";
  write_materials(x, scene, o, texrepeat);
  x << "    <material name=\"robot_mat\" rgba=\"0.9 0.4 0.1 1\"/>\n";
  x << "  </asset>\n  <worldbody>\n";

  write_scene_geoms(x, scene, sx, sy, cx, cy);

  // robots
  for (const RobotSpec& r : robots) write_robot(x, r);
  x << "  </worldbody>\n  <actuator>\n";
  write_actuators(x, robots, o);
  x << "  </actuator>\n</mujoco>\n";
  return x.str();
}

}  // namespace scancrew::sim
