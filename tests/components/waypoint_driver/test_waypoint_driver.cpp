// The waypoint driver on the sim backend: a ground robot and a multirotor go round a
// square in the test arena, passing every corner in order; stop_after_m stops the robot;
// a malformed waypoint list is refused at configuration.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "components/waypoint_driver/waypoint_driver.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::waypoint_driver {
namespace {

// Keeps the ground-truth poses.
class PoseLog final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps pose_gt";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  PoseLog(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}
  std::vector<msg::Odometry> poses;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::Odometry>("pose_gt", {.depth = 8},
                                       [this](Sample<msg::Odometry>&& s) { poses.push_back(*s); });
    return {};
  }
};
SCANCREW_REGISTER_COMPONENT(PoseLog, "test_pose_log")

// A 4 m square around the arena's central obstacle (0.8 m wide), corners at (±2, ±2).
constexpr const char* kSquare = "[2, -2, 1, 2, 2, 1, -2, 2, 1, -2, -2, 1]";

std::string launch_text(const std::string& kind, double duration_s, const std::string& driver) {
  return R"(
clock: sim
executor: {type: step}
run: {duration_s: )" +
         std::to_string(duration_s) + R"(, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: )" +
         kind +
         R"(, start: [-2.0, -2.0, 1.0, 0]}
remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params: {scene: )" SCANCREW_SOURCE_DIR
         R"(/launch_cfg/scenes/test_arena.yaml, publish_stereo: false, publish_depth: false}
  - {name: driver, type: waypoint_driver, params: )" +
         driver + R"(}
  - {name: log, type: test_pose_log}
)";
}

struct DriverRun {
  std::unique_ptr<Launch> launch;
  WaypointDriver* driver = nullptr;
  PoseLog* log = nullptr;
};

DriverRun run(const std::string& text) {
  DriverRun r;
  auto launch = Launch::from_string(text, "waypoint_test.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  if (!launch) return r;
  r.launch = std::move(launch).value();
  r.launch->run();
  r.driver = r.launch->find_component<WaypointDriver>();
  r.log = r.launch->find_component<PoseLog>();
  return r;
}

// Distance of (x, y) from the square's outline.
double off_square(double x, double y) {
  const double ax = std::abs(x), ay = std::abs(y);
  if (ax <= 2 && ay <= 2) return std::min(2 - ax, 2 - ay);
  return std::hypot(std::max(ax - 2, 0.0), std::max(ay - 2, 0.0));
}

void expect_laps(const std::string& kind, double max_off_m) {
  // one lap is 16 m; 50 s at 0.5 m/s with slowing in the corners: more than one lap
  DriverRun r = run(launch_text(kind, 50.0, std::string("{waypoints_m: ") + kSquare + "}"));
  ASSERT_NE(r.driver, nullptr);
  ASSERT_NE(r.log, nullptr);
  EXPECT_GE(r.driver->waypoints_reached(), 5u) << kind;  // every corner, then the first again
  EXPECT_GT(r.driver->travelled_m(), 16.0) << kind;
  EXPECT_LT(r.driver->travelled_m(), 25.5) << kind;  // at most 0.5 m/s
  EXPECT_FALSE(r.driver->stopped());
  // the robot stays near the square and visits each of its quadrants' corners
  bool corner[4] = {false, false, false, false};
  for (const msg::Odometry& o : r.log->poses) {
    const double x = o.T_world_body.position.x, y = o.T_world_body.position.y;
    EXPECT_LT(off_square(x, y), max_off_m) << kind << " at " << x << ", " << y;
    if (std::hypot(std::abs(x) - 2, std::abs(y) - 2) < 0.6) corner[(x > 0) + 2 * (y > 0)] = true;
    if (kind == "multirotor") EXPECT_NEAR(o.T_world_body.position.z, 1.0, 0.1);
  }
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(corner[c]) << kind << " corner " << c;
}

TEST(WaypointDriver, AGroundRobotGoesRoundASquarePassingEveryCorner) {
  expect_laps("ground", 0.6);
}

TEST(WaypointDriver, AMultirotorGoesRoundASquarePassingEveryCorner) {
  expect_laps("multirotor", 0.6);
}

TEST(WaypointDriver, StopsAfterTheGivenDistance) {
  DriverRun r = run(launch_text("ground", 20.0,
                                std::string("{stop_after_m: 3.0, waypoints_m: ") + kSquare + "}"));
  ASSERT_NE(r.driver, nullptr);
  ASSERT_NE(r.log, nullptr);
  EXPECT_TRUE(r.driver->stopped());
  EXPECT_NEAR(r.driver->travelled_m(), 3.0, 0.15);
  // still for the last 5 s
  const auto& p = r.log->poses;
  ASSERT_GT(p.size(), 60u);
  const msg::Vec3 a = p[p.size() - 50].T_world_body.position, b = p.back().T_world_body.position;
  EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 0.01);
}

TEST(WaypointDriver, RefusesAWaypointListThatIsNotTriples) {
  auto launch =
      Launch::from_string(launch_text("ground", 1.0, "{waypoints_m: [1, 2, 3, 4]}"), "bad.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("waypoints_m: needs x, y, z triples"), std::string::npos)
      << launch.error().front();
  launch = Launch::from_string(launch_text("ground", 1.0, "{}"), "none.yaml");
  ASSERT_FALSE(launch);
}

}  // namespace
}  // namespace scancrew::waypoint_driver
