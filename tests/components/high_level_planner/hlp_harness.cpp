// The high_level_planner tests' harness (hlp_harness.hpp): the scripted feeder and the plan
// log, registered here once for the test executable, and the helpers.

#include "tests/components/high_level_planner/hlp_harness.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "executors/registry.hpp"

namespace scancrew::high_level_planner::test {

Script g_script;  // NOLINT: set by each test before its launch runs

namespace {

class Feeder final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: scripted clusters and robot states";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  Feeder(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

 private:
  Result<void, std::string> on_configure() override {
    clusters_ = create_publisher<msg::ViewpointClusters>(g_script.clusters_topic);
    ises_ = create_publisher<msg::IseSet>(g_script.ises_topic);
    map_ = create_publisher<msg::MapUpdate>(g_script.map_topic);
    for (const TeamMember& m : team()) {
      states_.push_back(create_publisher<msg::RobotState>("/" + m.ns + "/robot_state"));
      requests_.push_back(create_publisher<msg::ReplanRequest>("/" + m.ns + "/replan_request"));
    }
    create_timer(std::chrono::milliseconds(50), [this] { tick(); });
    return {};
  }
  void tick() {
    const double t = static_cast<double>(clock().now_ns()) * 1e-9;
    const auto due = [&](double at) { return at <= t + 1e-9 && at > last_ + 1e-9; };
    for (const auto& [at, m] : g_script.ises)
      if (due(at))
        if (auto loan = ises_.loan()) {
          **loan = m;
          (*loan)->header.stamp_ns = msg::kStampUnset;
          (void)ises_.publish(std::move(*loan));
        }
    for (const auto& [at, snapshot] : g_script.maps)
      if (due(at))
        if (auto loan = map_.loan()) {
          (*loan)->map = snapshot;
          (*loan)->header.stamp_ns = msg::kStampUnset;
          (void)map_.publish(std::move(*loan));
        }
    for (const auto& [at, m] : g_script.clusters)
      if (due(at))
        if (auto loan = clusters_.loan()) {
          **loan = m;
          (*loan)->header.stamp_ns = msg::kStampUnset;
          (void)clusters_.publish(std::move(*loan));
        }
    for (const auto& [at, robot, s] : g_script.states)
      if (due(at))
        if (auto loan = states_[robot].loan()) {
          **loan = s;
          (*loan)->header.stamp_ns = msg::kStampUnset;
          (void)states_[robot].publish(std::move(*loan));
        }
    for (const auto& [at, robot, r] : g_script.requests)
      if (due(at))
        if (auto loan = requests_[robot].loan()) {
          **loan = r;
          (*loan)->header.stamp_ns = msg::kStampUnset;
          (void)requests_[robot].publish(std::move(*loan));
        }
    last_ = t;
  }
  Publisher<msg::ViewpointClusters> clusters_;
  Publisher<msg::IseSet> ises_;
  Publisher<msg::MapUpdate> map_;
  std::vector<Publisher<msg::RobotState>> states_;
  std::vector<Publisher<msg::ReplanRequest>> requests_;
  double last_ = -1;
};

// Keeps every plan published on /plan and /<ns>/plan.
class PlanLog final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps team plans";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  PlanLog(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}
  std::vector<msg::TeamPlan> plans;

 private:
  Result<void, std::string> on_configure() override {
    std::vector<std::string> topics{"/plan"};
    for (const TeamMember& m : team()) topics.push_back("/" + m.ns + "/plan");
    for (const std::string& t : topics)
      create_subscription<msg::TeamPlan>(
          t, {.depth = 16}, [this](Sample<msg::TeamPlan>&& s) { plans.push_back(*s); });
    return {};
  }
};
}  // namespace

SCANCREW_REGISTER_COMPONENT(Feeder, "test_hlp_feeder")
SCANCREW_REGISTER_COMPONENT(PlanLog, "test_hlp_plan_log")

// Random clusters in a 30 m square, 1-4 viewpoints each; every viewpoint sees two ISEs.
msg::ViewpointClusters random_clusters(size_t n, uint64_t seed, uint32_t types) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> xy(-15, 15), gain(0.01, 0.2), yaw(-3, 3);
  std::uniform_int_distribution<int> count(1, 4);
  msg::ViewpointClusters m;
  m.map_version = 7;
  m.ise_count = static_cast<uint32_t>(2 * n * 4);
  uint32_t ise = 0;
  for (size_t i = 0; i < n; ++i) {
    msg::ViewpointCluster c;
    c.id = static_cast<uint32_t>(100 + i);
    c.gain = gain(rng);
    c.robot_types = types;
    const double cx = xy(rng), cy = xy(rng);
    const int k = count(rng);
    for (int j = 0; j < k; ++j) {
      msg::Viewpoint v;
      v.pose.position = {cx + 0.5 * j, cy - 0.3 * j, 0.35};
      v.pose.yaw_rad = yaw(rng);
      v.seen_ise = {ise, ise + 1};
      ise += 2;
      v.robot_types = types;
      c.viewpoints.push_back(v);
    }
    c.centroid = c.viewpoints.front().pose.position;
    m.clusters.push_back(c);
  }
  return m;
}

msg::IseSet ises_for(const msg::ViewpointClusters& clusters) {
  msg::IseSet s;
  s.map_version = clusters.map_version;
  for (uint32_t i = 0; i < 2 * 4 * clusters.clusters.size(); ++i)
    s.centers_m.push_back({static_cast<double>(i), 0.5, 1.0});
  return s;
}

std::vector<PlanCluster> plan_clusters(const msg::ViewpointClusters& m) {
  std::vector<PlanCluster> out;
  for (const msg::ViewpointCluster& c : m.clusters) {
    PlanCluster p{.id = c.id, .gain = c.gain, .robot_types = c.robot_types, .viewpoints = {}};
    for (const msg::Viewpoint& v : c.viewpoints)
      p.viewpoints.emplace_back(v.pose.position.x, v.pose.position.y, v.pose.position.z);
    out.push_back(p);
  }
  return out;
}

std::string launch_text(const std::string& robots, const std::string& planner, double duration_s) {
  return R"(
clock: sim
executor: {type: step}
run: {duration_s: )" +
         std::to_string(duration_s) + R"(, sim_step_s: 0.05}
robots:)" +
         robots +
         R"(
remap: {pose: pose_gt}
components:
  - {name: feeder, type: test_hlp_feeder, per_robot: false}
  - )" + planner +
         R"(
  - {name: log, type: test_hlp_plan_log, per_robot: false}
)";
}

PlanRun run(const std::string& text) {
  PlanRun r;
  auto launch = Launch::from_string(text, "hlp_test.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  if (!launch) return r;
  r.launch = std::move(launch).value();
  r.launch->run();
  for (const auto& c : r.launch->components())
    if (auto* p = dynamic_cast<HighLevelPlanner*>(c.get())) r.planners.push_back(p);
  if (auto* log = r.launch->find_component<PlanLog>()) r.plans = log->plans;
  return r;
}

std::string config_errors(const std::string& text) {
  auto launch = Launch::from_string(text, "hlp_bad.yaml");
  if (!launch) {
    std::string all;
    for (const std::string& e : launch.error()) all += e + "\n";
    return all;
  }
  return "";
}

// robot id -> its clusters, from a plan's sequences
std::map<uint32_t, std::vector<uint32_t>> partition(const msg::TeamPlan& plan) {
  std::map<uint32_t, std::vector<uint32_t>> out;
  for (const msg::PathSequence& s : plan.sequences) out[s.robot_id] = s.cluster_ids;
  return out;
}

}  // namespace scancrew::high_level_planner::test
