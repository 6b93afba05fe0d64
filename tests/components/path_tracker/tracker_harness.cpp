// The path tracker tests' harness (tracker_harness.hpp): the test components' registrations,
// the injector, the launch text and the geometry.

#include "tests/components/path_tracker/tracker_harness.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace scancrew::path_tracker::testing {

SCANCREW_REGISTER_COMPONENT(TrackerLog, "test_tracker_log")

namespace {

// Sends what the traffic policy and a faulty planner or estimator would:
//   maneuvers  [t_s, kind (0 resume, 1 stop, 2 step aside), x, y, z, yaw_deg] sextuples
//   empty_path_at_s / empty_plan_id: an empty LocalPath at that time
//   nan_odom: a NaN pose on `odom` every 0.2 s
class TestInjector final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: maneuvers, empty paths, NaN poses";
  struct Config {
    std::vector<double> maneuvers;
    double empty_path_at_s = -1;
    uint64_t empty_plan_id = 0;
    bool nan_odom = false;
    bool lost_odom = false;  // finite poses with tracking quality 0 (the odometry lost track)
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional_list("maneuvers", c.maneuvers);
    p.optional("empty_path_at_s", c.empty_path_at_s);
    p.optional("empty_plan_id", c.empty_plan_id);
    p.optional("nan_odom", c.nan_odom);
    p.optional("lost_odom", c.lost_odom);
    return c;
  }
  TestInjector(ComponentContext c, Config config)
      : Component(std::move(c)), config_(std::move(config)) {}

 private:
  Result<void, std::string> on_configure() override {
    maneuver_ = create_publisher<msg::Maneuver>("maneuver");
    path_ = create_publisher<msg::LocalPath>("local_path");
    odom_ = create_publisher<msg::Odometry>("odom");
    create_timer(std::chrono::milliseconds(50), [this] { tick(); });
    return {};
  }
  void tick() {
    const double t = 1e-9 * static_cast<double>(clock().now_ns());
    for (; next_ + 5 < config_.maneuvers.size() && config_.maneuvers[next_] <= t + 1e-9;
         next_ += 6) {
      auto loan = maneuver_.loan();
      ASSERT_TRUE(loan);
      msg::Maneuver& m = **loan;
      m.kind = static_cast<msg::Maneuver::Kind>(static_cast<int>(config_.maneuvers[next_ + 1]));
      m.aside = {{config_.maneuvers[next_ + 2], config_.maneuvers[next_ + 3],
                  config_.maneuvers[next_ + 4]},
                 config_.maneuvers[next_ + 5] * M_PI / 180};
      (void)maneuver_.publish(std::move(*loan));
    }
    if (config_.empty_path_at_s >= 0 && t + 1e-9 >= config_.empty_path_at_s) {
      config_.empty_path_at_s = -1;
      auto loan = path_.loan();
      ASSERT_TRUE(loan);
      (**loan).plan_id = config_.empty_plan_id;
      (**loan).waypoints.clear();
      (void)path_.publish(std::move(*loan));
    }
    if (config_.nan_odom && std::llround(t * 20) % 4 == 0) {
      auto loan = odom_.loan();
      ASSERT_TRUE(loan);
      (**loan).T_world_body.position.x = std::numeric_limits<double>::quiet_NaN();
      (**loan).tracking_quality = 1.0;
      (void)odom_.publish(std::move(*loan));
    }
    if (config_.lost_odom && std::llround(t * 20) % 4 == 0) {
      auto loan = odom_.loan();
      ASSERT_TRUE(loan);
      (**loan).header.stamp_ns = clock().now_ns();
      (**loan).T_world_body.position = {-3, -2, 0};
      (**loan).tracking_quality = 0.0;
      (void)odom_.publish(std::move(*loan));
    }
  }
  Config config_;
  Publisher<msg::Maneuver> maneuver_;
  Publisher<msg::LocalPath> path_;
  Publisher<msg::Odometry> odom_;
  size_t next_ = 0;
};
SCANCREW_REGISTER_COMPONENT(TestInjector, "test_tracker_injector")

}  // namespace

std::string list(const std::vector<Waypoint4>& w) {
  std::string s = "[";
  for (const Waypoint4& p : w)
    s += std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + ", " +
         std::to_string(p.yaw_deg) + (&p == &w.back() ? "" : ", ");
  return s + "]";
}

std::string launch_text(const std::string& kind, const Waypoint4& start, double duration_s,
                        const std::string& player, const std::string& tracker,
                        const std::string& injector, const std::string& pose) {
  return R"(
clock: sim
executor: {type: step}
run: {duration_s: )" +
         std::to_string(duration_s) + R"(, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: )" +
         kind + ", start: [" + std::to_string(start.x) + ", " + std::to_string(start.y) + ", " +
         std::to_string(start.z) + ", " + std::to_string(start.yaw_deg) +
         R"(]}
remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params: {scene: )" SCANCREW_SOURCE_DIR
         R"(/launch_cfg/scenes/test_arena.yaml, publish_stereo: false, publish_depth: false}
  - {name: player, type: path_player, params: )" +
         player + R"(}
  - {name: tracker, type: path_tracker, remap: {pose: )" +
         pose + "}, params: " + tracker + R"(}
  - {name: log, type: test_tracker_log}
  - {name: inject, type: test_tracker_injector, params: )" +
         injector + R"(}
)";
}

TrackerRun run(const std::string& text) {
  TrackerRun r;
  auto launch = Launch::from_string(text, "tracker_test.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  if (!launch) return r;
  r.launch = std::move(launch).value();
  r.launch->run();
  r.tracker = r.launch->find_component<PathTracker>();
  r.log = r.launch->find_component<TrackerLog>();
  return r;
}

double t_s(const msg::Header& h) {
  return 1e-9 * static_cast<double>(h.stamp_ns);
}
double distance(const msg::Odometry& o, const Waypoint4& w, bool planar) {
  const auto& p = o.T_world_body.position;
  return std::sqrt((p.x - w.x) * (p.x - w.x) + (p.y - w.y) * (p.y - w.y) +
                   (planar ? 0.0 : (p.z - w.z) * (p.z - w.z)));
}
double yaw_of(const msg::Odometry& o) {
  const auto& q = o.T_world_body.orientation;
  return std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
}
double yaw_error_deg(const msg::Odometry& o, const Waypoint4& w) {
  return std::abs(std::remainder(w.yaw_deg * M_PI / 180 - yaw_of(o), 2 * M_PI)) * 180 / M_PI;
}
}  // namespace scancrew::path_tracker::testing
