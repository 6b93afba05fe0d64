// The sim backend in a composed graph, on sim time with the step executor: sensors at
// their rates, velocity commands applied, lockstep runs reproducible; on the wall clock
// with a multi-threaded executor: the physics follows the wall, with bounded catch-up.

#include <gtest/gtest.h>

#include <cmath>

#include "components/team_simulator/team_simulator.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "tests/components/constant_driver.hpp"

namespace scancrew::team_simulator {
namespace {

// Records what the robot's sensors deliver.
class Recorder final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: records sensor messages";
  struct Config {};
  static Config read_config(ParamReader&) { return {}; }
  Recorder(ComponentContext c, Config) : Component(std::move(c)) {}

  std::vector<int64_t> stereo_stamps, imu_stamps;
  std::vector<msg::Pose3> poses;
  uint64_t image_hash = 1469598103934665603ull;
  size_t depth_valid = 0, depth_frames = 0;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::StereoFrame>("stereo", {.depth = 4},
                                          [this](Sample<msg::StereoFrame>&& s) {
                                            stereo_stamps.push_back(s->header.stamp_ns);
                                            for (uint8_t b : s->left)
                                              image_hash = (image_hash ^ b) * 1099511628211ull;
                                          });
    create_subscription<msg::Imu>("imu", {.depth = 16}, [this](Sample<msg::Imu>&& s) {
      imu_stamps.push_back(s->header.stamp_ns);
    });
    create_subscription<msg::Odometry>("pose_gt", {.depth = 4}, [this](Sample<msg::Odometry>&& s) {
      poses.push_back(s->T_world_body);
    });
    create_subscription<msg::DepthImage>("depth", {.depth = 4},
                                         [this](Sample<msg::DepthImage>&& s) {
                                           ++depth_frames;
                                           for (float z : s->depth_m)
                                             depth_valid += std::isnan(z) ? 0 : 1;
                                         });
    return {};
  }
};

SCANCREW_REGISTER_COMPONENT(Recorder, "test_recorder")

std::string launch_text(const char* scene) {
  return std::string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 2.0, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: ground, start: [-1.0, -1.0, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [-1.0, 1.0, 0, 0]}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params:
      scene: )") +
         scene + R"(
      seed: 3
      ground_camera_width: 160
      ground_camera_height: 93
      ground_camera_rate_hz: 5
      imu_rate_hz: 50
  - {name: driver, type: test_constant_driver, params: {vx: 0.5}}
  - {name: recorder, type: test_recorder}
)";
}

struct RunResult {
  std::vector<Recorder*> recorders;
  std::unique_ptr<Launch> launch;
};

RunResult run_once() {
  auto launch = Launch::from_string(launch_text(SCANCREW_SOURCE_DIR "/launch_cfg/scenes/tiny.yaml"),
                                    "sim.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  RunResult r;
  if (!launch) return r;
  r.launch = std::move(launch).value();
  r.launch->run();
  for (const auto& c : r.launch->components())
    if (auto* rec = dynamic_cast<Recorder*>(c.get())) r.recorders.push_back(rec);
  return r;
}

TEST(TeamSimulator, PublishesEveryRobotsSensorsAtTheirRatesOnSimTime) {
  RunResult run = run_once();
  ASSERT_EQ(run.recorders.size(), 2u);
  for (Recorder* rec : run.recorders) {
    // 2 s at 5 Hz, the first frame at t = 0.01 s (first physics tick)
    ASSERT_EQ(rec->stereo_stamps.size(), 10u);
    EXPECT_EQ(rec->stereo_stamps[1] - rec->stereo_stamps[0], 200'000'000);
    EXPECT_NEAR(static_cast<double>(rec->imu_stamps.size()), 100.0, 1.0);
    EXPECT_EQ(rec->depth_frames, 10u);
    EXPECT_GT(rec->depth_valid, 0u);
  }
}

TEST(TeamSimulator, VelocityCommandsMoveTheRobots) {
  RunResult run = run_once();
  ASSERT_EQ(run.recorders.size(), 2u);
  for (Recorder* rec : run.recorders) {
    ASSERT_GE(rec->poses.size(), 2u);
    // driving at 0.5 m/s from the first command (t = 0.1 s) on; the last pose is at t = 1.81 s
    EXPECT_NEAR(rec->poses.back().position.x - rec->poses.front().position.x, 0.5 * 1.7, 0.06);
  }
}

TEST(TeamSimulator, TwoLockstepRunsGiveIdenticalSensorsAndTrajectories) {
  RunResult a = run_once(), b = run_once();
  ASSERT_EQ(a.recorders.size(), 2u);
  ASSERT_EQ(b.recorders.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(a.recorders[i]->image_hash, b.recorders[i]->image_hash);
    EXPECT_EQ(a.recorders[i]->stereo_stamps, b.recorders[i]->stereo_stamps);
    ASSERT_EQ(a.recorders[i]->poses.size(), b.recorders[i]->poses.size());
    for (size_t k = 0; k < a.recorders[i]->poses.size(); ++k)
      EXPECT_EQ(a.recorders[i]->poses[k].position.x, b.recorders[i]->poses[k].position.x);
  }
}

// The launch on the wall clock with a multi-threaded executor, for `duration_s` of wall time.
RunResult run_on_wall_clock(double duration_s, const std::string& sim_params = "") {
  std::string text = launch_text(SCANCREW_SOURCE_DIR "/launch_cfg/scenes/tiny.yaml");
  text.replace(text.find("clock: sim"), 10, "clock: wall");
  text.replace(text.find("executor: {type: step}"), 22,
               "executor: {type: multi_threaded, threads: 2}");
  text.replace(text.find("duration_s: 2.0"), 15, "duration_s: " + std::to_string(duration_s));
  text.replace(text.find("      seed: 3\n"), 14, "      seed: 3\n" + sim_params);
  auto launch = Launch::from_string(text, "wall.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  RunResult r;
  if (!launch) return r;
  r.launch = std::move(launch).value();
  r.launch->run();
  for (const auto& c : r.launch->components())
    if (auto* rec = dynamic_cast<Recorder*>(c.get())) r.recorders.push_back(rec);
  return r;
}

// Wall-clock runs are not reproducible: ranges only, wide enough for a loaded 2-core machine.
TEST(TeamSimulator, StepsThePhysicsToWallTimeOnAMultiThreadedExecutor) {
  const int64_t before_ns = WallClock().now_ns();
  RunResult run = run_on_wall_clock(1.5);
  ASSERT_EQ(run.recorders.size(), 2u);
  const RunSummary summary = run.launch->summary();
  ASSERT_TRUE(summary.wall_clock_sim.has_value());
  const RunSummary::WallClockSim& w = *summary.wall_clock_sim;
  // the physics followed the wall: 1.5 s, less the start-up and the last tick's period
  EXPECT_GT(w.simulated_s, 1.0);
  EXPECT_LT(w.simulated_s, 1.6);
  EXPECT_GT(w.ticks, 50u);  // 100 Hz timer
  EXPECT_LT(w.ticks, 160u);
  EXPECT_LE(w.late_ticks, w.ticks);
  for (Recorder* rec : run.recorders) {
    // camera at 5 Hz on the wall clock, stamped with the physics time: 0.2 s apart on
    // average (drift-free); one gap is off by at most a catch-up step (0.1 s) either way
    ASSERT_GE(rec->stereo_stamps.size(), 5u);
    EXPECT_LE(rec->stereo_stamps.size(), 9u);
    EXPECT_GT(rec->stereo_stamps.front(), before_ns);
    const double mean_gap_s =
        static_cast<double>(rec->stereo_stamps.back() - rec->stereo_stamps.front()) * 1e-9 /
        static_cast<double>(rec->stereo_stamps.size() - 1);
    EXPECT_GE(mean_gap_s, 0.19);
    EXPECT_LE(mean_gap_s, 0.26);
    for (size_t k = 1; k < rec->stereo_stamps.size(); ++k) {
      const int64_t gap = rec->stereo_stamps[k] - rec->stereo_stamps[k - 1];
      EXPECT_GE(gap, 95'000'000) << k;
      EXPECT_LE(gap, 350'000'000) << k;
    }
    EXPECT_GT(rec->depth_valid, 0u);  // rendered from the executor's threads
    // driving at 0.5 m/s for most of the run
    ASSERT_GE(rec->poses.size(), 2u);
    const double moved = rec->poses.back().position.x - rec->poses.front().position.x;
    EXPECT_GT(moved, 0.25);
    EXPECT_LT(moved, 0.8);
  }
}

TEST(TeamSimulator, CatchesUpWithTheWallAtMostMaxCatchUpPerTick) {
  // 2 ms of physics (or one MuJoCo step) per 10 ms tick at most: the physics falls behind,
  // the ticks say so
  RunResult run = run_on_wall_clock(1.0, "      max_catch_up_s: 0.002\n");
  ASSERT_EQ(run.recorders.size(), 2u);
  const RunSummary summary = run.launch->summary();
  ASSERT_TRUE(summary.wall_clock_sim.has_value());
  const RunSummary::WallClockSim& w = *summary.wall_clock_sim;
  // a tick steps one MuJoCo step at least
  const auto* sim = run.launch->find_component<TeamSimulator>();
  ASSERT_NE(sim, nullptr);
  const double cap_s = std::max(0.002, static_cast<double>(sim->simulator()->timestep_ns()) * 1e-9);
  EXPECT_LT(cap_s, 0.01);  // below the tick period: the physics falls behind
  EXPECT_GT(w.simulated_s, 0.0);
  EXPECT_LE(w.simulated_s, cap_s * static_cast<double>(w.ticks) + 1e-6);
  EXPECT_GT(w.max_lag_s, 0.3);
  EXPECT_GT(w.capped_ticks, w.ticks / 2);
  EXPECT_GT(w.late_ticks, w.ticks / 2);
}

TEST(TeamSimulator, RefusesABadScene) {
  auto launch = Launch::from_string(launch_text("/nonexistent/scene.yaml"), "bad.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("cannot read the scene file: no such file"),
            std::string::npos)
      << launch.error().front();
  // a device is refused before it is read (/dev/zero never ends: it was read to bad_alloc)
  for (const char* device : {"/dev/zero", "/dev/urandom"}) {
    launch = Launch::from_string(launch_text(device), "bad.yaml");
    ASSERT_FALSE(launch) << device;
    EXPECT_NE(launch.error().front().find("not a regular file"), std::string::npos)
        << launch.error().front();
  }
}

TEST(TeamSimulator, RefusesARobotStartingInsideAnObstacle) {
  std::string text = launch_text(SCANCREW_SOURCE_DIR "/launch_cfg/scenes/tiny.yaml");
  text.replace(text.find("start: [-1.0, -1.0, 0, 0]"), 25,
               "start: [1.0, 0.5, 0, 0]  ");  // the block
  auto launch = Launch::from_string(text, "inside.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("r1 starts inside 'block'"), std::string::npos)
      << launch.error().front();
}

}  // namespace
}  // namespace scancrew::team_simulator
