// The trajectory_player component (a recorded mission's paths.csv flown again through the
// path tracker) in the test arena on sim time: a multirotor follows a timed recording (a
// straight run, a turn on the spot, a climb) close to each recorded pose at its time, and
// ends at the last one; a missing file, a robot without rows and times that do not increase
// are refused with why.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "components/trajectory_player/trajectory_player.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::trajectory_player {
namespace {

// Keeps robot 1's ground-truth poses.
class PoseLog final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps pose_gt";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  PoseLog(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}
  std::vector<msg::Odometry> poses;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::Odometry>("/r1/pose_gt", {.depth = 8},
                                       [this](Sample<msg::Odometry>&& s) { poses.push_back(*s); });
    return {};
  }
};
SCANCREW_REGISTER_COMPONENT(PoseLog, "test_trajectory_pose_log")

struct Pose4 {
  double t, x, y, z, yaw;
};

// Every 0.5 s: 5 s along +x at 0.4 m/s, a quarter turn on the spot over 3 s, a 1 m climb
// over 4 s, then 2 s at rest.
std::vector<Pose4> recording() {
  std::vector<Pose4> r;
  for (int k = 0; k <= 28; ++k) {
    const double t = 0.5 * k;
    Pose4 p{t, -2.5, -2.0, 1.0, 0.0};
    p.x += 0.4 * std::min(t, 5.0);
    p.yaw = M_PI / 2 * std::clamp((t - 5.0) / 3.0, 0.0, 1.0);
    p.z += std::clamp((t - 8.0) / 4.0, 0.0, 1.0);
    r.push_back(p);
  }
  return r;
}

std::string write_csv(const std::string& name, const std::vector<Pose4>& poses, uint32_t robot) {
  std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream f(path);
  f << "t_s,robot_id,x_m,y_m,z_m,yaw_rad\n";
  char line[160];
  for (const Pose4& p : poses) {
    std::snprintf(line, sizeof line, "%.3f,%u,%.4f,%.4f,%.4f,%.4f\n", p.t, robot, p.x, p.y, p.z,
                  p.yaw);
    f << line;
  }
  return path;
}

std::string launch_text(const std::string& csv) {
  return R"(
clock: sim
executor: {type: step}
run: {duration_s: 16.0, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: multirotor, start: [-2.5, -2.0, 1.0, 0]}
remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params: {scene: )" SCANCREW_SOURCE_DIR
         R"(/launch_cfg/scenes/test_arena.yaml, publish_stereo: false, publish_depth: false}
  - {name: player, type: trajectory_player, params: {paths_csv: )" +
         csv + R"(}}
  - {name: tracker, type: path_tracker, params: {}}
  - {name: log, type: test_trajectory_pose_log, per_robot: false}
)";
}

double yaw_of(const msg::Odometry& o) {
  const auto& q = o.T_world_body.orientation;
  return std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
}

TEST(TrajectoryPlayer, AMultirotorFollowsTheRecordingInTime) {
  const std::vector<Pose4> rec = recording();
  auto launch = Launch::from_string(launch_text(write_csv("scancrew_traj_ok.csv", rec, 1)), "t");
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  const auto* log = (*launch)->find_component<PoseLog>();
  const auto* player = (*launch)->find_component<TrajectoryPlayer>();
  ASSERT_NE(log, nullptr);
  ASSERT_NE(player, nullptr);
  EXPECT_EQ(player->samples(), rec.size());
  ASSERT_FALSE(log->poses.empty());
  // at each recorded time, the robot near the pose recorded then (it aims lead_s ahead)
  double worst_m = 0, worst_deg = 0, sum_m = 0;
  size_t n = 0;
  for (const Pose4& p : rec) {
    const msg::Odometry* at = nullptr;
    for (const msg::Odometry& o : log->poses)
      if (std::abs(1e-9 * static_cast<double>(o.header.stamp_ns) - p.t) < 0.026) at = &o;
    if (at == nullptr) continue;
    const auto& q = at->T_world_body.position;
    const double e = std::hypot(q.x - p.x, q.y - p.y, q.z - p.z);
    worst_m = std::max(worst_m, e);
    sum_m += e;
    ++n;
    worst_deg =
        std::max(worst_deg, std::abs(std::remainder(yaw_of(*at) - p.yaw, 2 * M_PI)) * 180 / M_PI);
  }
  ASSERT_GT(n, rec.size() / 2);
  EXPECT_LT(sum_m / static_cast<double>(n), 0.2);
  EXPECT_LT(worst_m, 0.4);
  EXPECT_LT(worst_deg, 25.0);
  // at rest at the last pose
  const auto& end = log->poses.back().T_world_body.position;
  EXPECT_LT(std::hypot(end.x - rec.back().x, end.y - rec.back().y, end.z - rec.back().z), 0.1);
  std::printf("[figures] trajectory replay: mean %.3f m, worst %.3f m, worst yaw %.1f deg\n",
              sum_m / static_cast<double>(n), worst_m, worst_deg);
}

TEST(TrajectoryPlayer, RefusesAMissingFileARobotWithoutRowsAndTimesThatDoNotIncrease) {
  auto missing = Launch::from_string(launch_text("/nonexistent/paths.csv"), "t");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().front().find("cannot read '/nonexistent/paths.csv': no such file"),
            std::string::npos)
      << missing.error().front();
  auto other =
      Launch::from_string(launch_text(write_csv("scancrew_traj_r2.csv", recording(), 2)), "t");
  ASSERT_FALSE(other);
  EXPECT_NE(other.error().front().find("no row for robot 1"), std::string::npos)
      << other.error().front();
  std::vector<Pose4> back = recording();
  back[3].t = back[2].t;
  auto repeated =
      Launch::from_string(launch_text(write_csv("scancrew_traj_rep.csv", back, 1)), "t");
  ASSERT_FALSE(repeated);
  EXPECT_NE(repeated.error().front().find("do not increase"), std::string::npos)
      << repeated.error().front();
}

}  // namespace
}  // namespace scancrew::trajectory_player
