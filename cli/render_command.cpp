#include "cli/render_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "cli/choices.hpp"
#include "cli/commands.hpp"
#include "executors/log.hpp"
#include "sim/png_writer.hpp"
#include "sim/team_sim.hpp"

namespace scancrew::cli {

namespace {

sim::RobotSpec make_robot(const RenderOptions& o, double x, double y, double yaw) {
  sim::RobotSpec r;
  r.id = 1;
  r.name = "viewer";
  r.kind = o.kind;
  r.start_x_m = x;
  r.start_y_m = y;
  r.start_z_m = o.z_m;
  r.start_yaw_rad = yaw;
  r.camera.width = o.width;
  r.camera.height = o.height;
  r.camera.max_range_m = 50;
  if (r.kind == robot::RobotKind::kMultirotor) {
    r.camera.baseline_m = 0.11;
    r.camera.mount_up_m = 0.0;
  }
  r.depth_noise.enabled = false;
  return r;
}

// The poses to try the viewer at: {x m, y m, yaw rad}.
std::vector<std::array<double, 3>> candidate_poses(const RenderOptions& o,
                                                   const sim::SceneSpec& scene, double cx,
                                                   double cy) {
  // candidate poses: the one asked for, else the corners (1 m in) facing the centre
  std::vector<std::array<double, 3>> candidates;
  if (o.pose.size() == 3) {
    candidates.push_back({o.pose[0], o.pose[1], o.pose[2] * M_PI / 180.0});
  } else {
    for (bool east : {false, true})
      for (bool north : {false, true}) {
        const double x = east ? scene.max_m.x - 1 : scene.min_m.x + 1;
        const double y = north ? scene.max_m.y - 1 : scene.min_m.y + 1;
        candidates.push_back({x, y, std::atan2(cy - y, cx - x)});
      }
  }
  return candidates;
}

// The simulator with the viewer at the first candidate pose it accepts; else the last error.
Result<std::unique_ptr<sim::TeamSim>, std::string> create_viewer(
    const RenderOptions& o, const sim::SceneSpec& scene,
    const std::vector<std::array<double, 3>>& candidates) {
  std::string last_error;
  for (const auto& [x, y, yaw] : candidates) {
    sim::TeamSimConfig config;
    auto made = sim::TeamSim::create(scene, {make_robot(o, x, y, yaw)}, config);
    if (made) return std::move(made).value();
    last_error = made.error();
  }
  return make_unexpected(last_error);
}

}  // namespace

int run_render(const RenderOptions& o) {
  auto scene = sim::load_scene(o.scene_path);
  if (!scene) {
    std::fprintf(stderr, "scancrew render: %zu error(s) in the scene\n", scene.error().size());
    for (const auto& e : scene.error())
      std::fprintf(stderr, "  %s\n", scancrew::log::printable(e).c_str());
    return 2;
  }
  const double cx = 0.5 * (scene->min_m.x + scene->max_m.x),
               cy = 0.5 * (scene->min_m.y + scene->max_m.y);
  auto made = create_viewer(o, *scene, candidate_poses(o, *scene, cx, cy));
  if (!made) {
    std::fprintf(stderr, "scancrew render: %s\n", made.error().c_str());
    return 2;
  }
  const std::unique_ptr<sim::TeamSim> team = std::move(made).value();
  std::filesystem::create_directories(o.out_dir);
  msg::StereoFrame stereo;
  msg::DepthImage depth;
  if (auto r = team->render_stereo(0, &stereo, &depth); !r) {
    std::fprintf(stderr, "scancrew render: %s\n", scancrew::log::printable(r.error()).c_str());
    return 2;
  }
  const auto path = [&](const char* name) {
    return (std::filesystem::path(o.out_dir) / name).string();
  };
  const unsigned w = stereo.intrinsics.width, h = stereo.intrinsics.height;
  std::vector<std::string> written;
  const auto write = [&](const char* name, const std::vector<uint8_t>& px, unsigned pw, unsigned ph,
                         int channels) {
    auto r = sim::write_png(path(name), px, pw, ph, channels);
    if (!r) {
      std::fprintf(stderr, "scancrew render: %s\n", scancrew::log::printable(r.error()).c_str());
      return false;
    }
    written.push_back(path(name));
    return true;
  };
  if (!write("left.png", stereo.left, w, h, 1) || !write("right.png", stereo.right, w, h, 1))
    return 2;
  if (!write("depth.png", sim::colorize_depth(depth.depth_m, 0.0f, 10.0f), w, h, 3)) return 2;

  // from above: high enough for the whole bounds to fit the vertical FOV
  const double fov_v = 60.0, tw = 640, th = 480;
  const double half_y = 0.5 * (scene->max_m.y - scene->min_m.y),
               half_x = 0.5 * (scene->max_m.x - scene->min_m.x);
  const double tan_v = std::tan(fov_v * M_PI / 360.0);
  const double height =
      std::max(half_y / tan_v, half_x / (tan_v * tw / th)) * 1.05 + scene->max_m.z;
  std::vector<uint8_t> top;
  if (auto r = team->render_view({cx, cy, height}, {0.0, 0.0, -1.0}, fov_v, 640, 480, true, &top,
                                 nullptr);
      !r) {
    std::fprintf(stderr, "scancrew render: %s\n", scancrew::log::printable(r.error()).c_str());
    return 2;
  }
  if (!write("top_view.png", top, 640, 480, 3)) return 2;
  const msg::Pose3 pose = team->body_pose(0);
  std::printf("scene '%s': camera at (%.2f, %.2f, %.2f), %ux%u, f = %.1f px, baseline %.2f m\n",
              scene->name.c_str(), pose.position.x, pose.position.y, depth.T_world_cam.position.z,
              w, h, stereo.intrinsics.fx, stereo.baseline_m);
  for (const auto& p : written) std::printf("wrote %s\n", p.c_str());
  return 0;
}

void add_render_command(CLI::App& app, CommandTable& table) {
  auto [render, o] = table.add_with_options<RenderOptions>(
      app, "render", "render a scene: stereo pair, depth and a top view, as PNG", run_render);
  render->add_option("scene", o->scene_path, "scene file (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  render->add_option("--out", o->out_dir, "output folder")->required();
  render->add_option("--pose", o->pose, "x,y,yaw_deg of the robot (default: a free corner)")
      ->delimiter(',')
      ->expected(3);
  RenderOptions* options = o;  // o, a structured binding, is no lambda capture for clang < 16
  render
      ->add_option_function<std::string>(
          "--kind",
          [options](const std::string& name) {
            // IsMember has checked the name
            options->kind = value_of(robot::kRobotKindNames, name).value_or(options->kind);
          },
          "robot kind")
      ->check(CLI::IsMember(name_list(robot::kRobotKindNames)));
  render->add_option("--z", o->z_m, "multirotor altitude, m");
  render->add_option("--width", o->width, "image width")->check(CLI::Range(16u, 1920u));
  render->add_option("--height", o->height, "image height (with the width, sets the FOV aspect)")
      ->check(CLI::Range(16u, 1080u));
}

}  // namespace scancrew::cli
