// The high_level_planner component on sim time with the step executor, fed by a scripted
// test component (clusters, ISEs, poses, robot states at chosen times): the centralized
// TSGA plan matches plan_tsga and carries yaws, cluster ids and C_start; dist-TSGA on every
// robot gives TSGA's partition; an idle robot gets the clusters nobody holds; NNB; a
// heterogeneous team; roadmap distances (a wall reorders a tour; the straight line until
// the first map); bad input and bad configuration; a lost robot (kLost, as the dds_bridge
// reports a dead process) is left out and its clusters go to the others, until it is back.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "components/high_level_planner/high_level_planner.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "interfaces/map_update.hpp"
#include "tests/core/motion/box_world.hpp"

namespace scancrew::high_level_planner {
namespace {

// What the scripted feeder publishes, and when (sim seconds).
struct Script {
  std::vector<std::pair<double, msg::ViewpointClusters>> clusters;
  std::vector<std::pair<double, msg::IseSet>> ises;
  // (time, robot index in the team, state)
  std::vector<std::tuple<double, size_t, msg::RobotState>> states;
  std::vector<std::pair<double, std::shared_ptr<const tsdf::MapSnapshot>>> maps;
  // (time, robot index in the team, request) on /<ns>/replan_request
  std::vector<std::tuple<double, size_t, msg::ReplanRequest>> requests;
  std::string clusters_topic = "/clusters";
  std::string ises_topic = "/ises";
  std::string map_topic = "/map";
};
Script g_script;  // NOLINT: set by each test before its launch runs

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

SCANCREW_REGISTER_COMPONENT(Feeder, "test_hlp_feeder")
SCANCREW_REGISTER_COMPONENT(PlanLog, "test_hlp_plan_log")

// Random clusters in a 30 m square, 1-4 viewpoints each; every viewpoint sees two ISEs.
msg::ViewpointClusters random_clusters(size_t n, uint64_t seed, uint32_t types = 3) {
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

const std::string kThreeGround = R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [10, -10, 0, 0]}
  - {id: 3, namespace: r3, kind: ground, start: [0, 12, 0, 0]})";

std::string launch_text(const std::string& robots, const std::string& planner,
                        double duration_s = 1.0) {
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

struct PlanRun {
  std::unique_ptr<Launch> launch;
  std::vector<msg::TeamPlan> plans;
  std::vector<HighLevelPlanner*> planners;
};

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

TEST(HighLevelPlanner, CentralizedTsgaPublishesTheTsgaPlanWithYawsAndIses) {
  const msg::ViewpointClusters clusters = random_clusters(15, 3);
  g_script = {};
  g_script.ises = {{0.1, ises_for(clusters)}};
  g_script.clusters = {{0.2, clusters}};
  PlanRun r = run(launch_text(kThreeGround,
                              "{name: hlp, type: high_level_planner, per_robot: false, params: "
                              "{algorithm: tsga}}"));
  ASSERT_EQ(r.plans.size(), 1u);
  const msg::TeamPlan& plan = r.plans.front();
  EXPECT_EQ(plan.map_version, 7u);
  ASSERT_EQ(plan.sequences.size(), 3u);

  const std::vector<PlanRobot> robots{{.id = 1, .type_bit = 1, .position = {-10, -10, 0}},
                                      {.id = 2, .type_bit = 1, .position = {10, -10, 0}},
                                      {.id = 3, .type_bit = 1, .position = {0, 12, 0}}};
  auto expected = plan_tsga(robots, plan_clusters(clusters));
  ASSERT_TRUE(expected) << expected.error();
  std::multiset<uint32_t> all;
  for (size_t k = 0; k < 3; ++k) {
    const msg::PathSequence& s = plan.sequences[k];
    EXPECT_EQ(s.robot_id, robots[k].id);
    EXPECT_EQ(s.cluster_ids, expected->robots[k].clusters);
    EXPECT_NEAR(s.utility, expected->robots[k].utility, 1e-12);
    ASSERT_EQ(s.cluster_utilities.size(), s.cluster_ids.size());
    ASSERT_EQ(s.viewpoint_clusters.size(), s.viewpoints.size());
    all.insert(s.cluster_ids.begin(), s.cluster_ids.end());
    // every viewpoint is one of its cluster's, with that viewpoint's yaw; C_start holds the
    // ISEs the viewpoints see
    size_t seen = 0;
    for (size_t i = 0; i < s.viewpoints.size(); ++i) {
      const msg::ViewpointCluster& c = clusters.clusters[s.viewpoint_clusters[i] - 100];
      bool found = false;
      for (const msg::Viewpoint& v : c.viewpoints)
        found = found || (v.pose.position.x == s.viewpoints[i].position.x &&
                          v.pose.position.y == s.viewpoints[i].position.y &&
                          v.pose.yaw_rad == s.viewpoints[i].yaw_rad);
      EXPECT_TRUE(found) << "viewpoint " << i << " of robot " << s.robot_id;
      seen += 2;
    }
    EXPECT_EQ(s.ise_centers_m.size(), seen);
  }
  EXPECT_EQ(all.size(), clusters.clusters.size());
  EXPECT_EQ(std::set<uint32_t>(all.begin(), all.end()).size(), clusters.clusters.size());
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().plans, 1u);
}

TEST(HighLevelPlanner, DistTsgaOnEveryRobotGivesTheCentralizedPartition) {
  const msg::ViewpointClusters clusters = random_clusters(20, 11);
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  PlanRun central =
      run(launch_text(kThreeGround, "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(central.plans.size(), 1u);

  // every robot's instance reads its own /<ns>/clusters: all three get the same message
  g_script.clusters_topic = "/shared_clusters";
  PlanRun dist = run(launch_text(kThreeGround,
                                 "{name: hlp, type: high_level_planner, remap: {clusters: "
                                 "/shared_clusters}, params: {algorithm: dist_tsga}}"));
  ASSERT_EQ(dist.planners.size(), 3u);
  ASSERT_EQ(dist.plans.size(), 3u);
  std::map<uint32_t, std::vector<uint32_t>> merged;
  for (const msg::TeamPlan& p : dist.plans) {
    ASSERT_EQ(p.sequences.size(), 1u) << "a dist-TSGA robot publishes its own path only";
    merged[p.sequences[0].robot_id] = p.sequences[0].cluster_ids;
  }
  EXPECT_EQ(merged, partition(central.plans.front()));
}

TEST(HighLevelPlanner, AReplanRequestPlansAgainForTheRobotsThisInstancePlansFor) {
  // clusters at 0.2 s: one plan; a request before them (0.1 s) has nothing to plan from; a
  // request at 0.5 s plans again (the centralized instance plans for everyone; of the
  // dist-TSGA instances only the asking robot's plans)
  const msg::ViewpointClusters clusters = random_clusters(12, 5);
  msg::ReplanRequest utility;
  utility.reason = msg::ReplanRequest::Reason::kUtility;
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  g_script.requests = {{0.1, 0, utility}, {0.5, 1, utility}};
  PlanRun central =
      run(launch_text(kThreeGround, "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(central.planners.size(), 1u);
  EXPECT_EQ(central.plans.size(), 2u);
  EXPECT_EQ(central.planners[0]->stats().plans, 2u);
  EXPECT_EQ(central.planners[0]->stats().requests, 1u);

  g_script.clusters_topic = "/shared_clusters";
  PlanRun dist = run(launch_text(kThreeGround,
                                 "{name: hlp, type: high_level_planner, remap: {clusters: "
                                 "/shared_clusters}, params: {algorithm: dist_tsga}}"));
  ASSERT_EQ(dist.planners.size(), 3u);
  EXPECT_EQ(dist.plans.size(), 4u);  // one each on the clusters, robot 2's on its request
  for (const HighLevelPlanner* p : dist.planners) {
    const bool asked = p->robot_id() == 2;
    EXPECT_EQ(p->stats().requests, asked ? 1u : 0u) << p->robot_id();
    EXPECT_EQ(p->stats().plans, asked ? 2u : 1u) << p->robot_id();
  }
}

TEST(HighLevelPlanner, AnIdleRobotGetsTheClustersNobodyHolds) {
  const msg::ViewpointClusters first = random_clusters(12, 5);
  msg::ViewpointClusters second = random_clusters(18, 5);  // the first 12 and 6 new ones
  second.map_version = 8;
  // the first 12 with one viewpoint each now: the other robots' plans index viewpoints
  // these clusters no longer hold (an out-of-range crash when their sequences were
  // published again with the idle robot's)
  for (size_t i = 0; i < 12; ++i) second.clusters[i].viewpoints.resize(1);
  g_script = {};
  g_script.clusters = {{0.1, first}, {0.3, second}};  // the second is throttled
  msg::RobotState moving, idle;
  moving.mode = msg::RobotState::Mode::kMoving;
  moving.T_world_body.position = {10, -10, 0};
  idle.mode = msg::RobotState::Mode::kIdle;
  idle.T_world_body.position = {12, -8, 0};
  g_script.states = {{0.2, 1, moving}, {0.5, 1, idle}};
  PlanRun r = run(launch_text(kThreeGround,
                              "{name: hlp, type: high_level_planner, per_robot: false, params: "
                              "{min_replan_period_s: 100}}"));
  ASSERT_EQ(r.plans.size(), 2u);
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().reallocations, 1u);
  EXPECT_EQ(r.planners[0]->stats().skipped, 1u);  // the throttled update
  auto before = partition(r.plans[0]);
  auto after = partition(r.plans[1]);
  // only the idle robot's sequence is published: the others keep their tours
  EXPECT_EQ(after.count(1), 0u);
  EXPECT_EQ(after.count(3), 0u);
  ASSERT_FALSE(after[2].empty());
  std::set<uint32_t> held(before[1].begin(), before[1].end());
  held.insert(before[3].begin(), before[3].end());
  for (uint32_t c : after[2]) EXPECT_EQ(held.count(c), 0u) << c;
  // it takes every cluster nobody else holds (its old ones and the 6 new ones)
  EXPECT_EQ(after[2].size(), second.clusters.size() - held.size());
  EXPECT_EQ(r.plans[1].map_version, 8u);
}

TEST(HighLevelPlanner, NnbGivesEachRobotOneCluster) {
  const msg::ViewpointClusters clusters = random_clusters(10, 2);
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  PlanRun r = run(launch_text(kThreeGround,
                              "{name: hlp, type: high_level_planner, per_robot: false, params: "
                              "{algorithm: nnb}}"));
  ASSERT_EQ(r.plans.size(), 1u);
  ASSERT_EQ(r.plans[0].sequences.size(), 3u);
  for (const msg::PathSequence& s : r.plans[0].sequences) EXPECT_EQ(s.cluster_ids.size(), 1u);
}

TEST(HighLevelPlanner, HeterogeneousTeamOnlyGetsReachableClusters) {
  msg::ViewpointClusters clusters = random_clusters(12, 9);
  for (size_t i = 0; i < clusters.clusters.size(); ++i)
    clusters.clusters[i].robot_types = i % 3 == 0 ? msg::kMultirotorBit : 3;
  clusters.clusters[5].robot_types = 0;  // nobody can reach it
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  PlanRun r = run(launch_text(R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: u2, kind: multirotor, start: [10, 10, 3, 0]})",
                              "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(r.plans.size(), 1u);
  EXPECT_EQ(r.plans[0].unassigned, std::vector<uint32_t>{105});
  auto p = partition(r.plans[0]);
  for (uint32_t c : p[1]) EXPECT_NE((c - 100) % 3, 0u) << "a UAV-only cluster went to the UGV";
  EXPECT_EQ(p[1].size() + p[2].size(), clusters.clusters.size() - 1);
}

TEST(HighLevelPlanner, BadClustersAreSkippedAndTheNextGoodOnesPlanned) {
  msg::ViewpointClusters bad = random_clusters(6, 4);
  bad.clusters[2].gain = std::numeric_limits<double>::quiet_NaN();
  msg::ViewpointClusters duplicate = random_clusters(6, 4);
  duplicate.clusters[3].id = duplicate.clusters[1].id;
  const msg::ViewpointClusters good = random_clusters(6, 4);
  g_script = {};
  g_script.clusters = {{0.1, bad}, {0.3, duplicate}, {0.5, good}};
  PlanRun r =
      run(launch_text(kThreeGround, "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().skipped, 2u);
  ASSERT_EQ(r.plans.size(), 1u);
  size_t assigned = 0;
  for (const msg::PathSequence& s : r.plans[0].sequences) assigned += s.cluster_ids.size();
  EXPECT_EQ(assigned, 6u);
}

msg::RobotState state_of(msg::RobotState::Mode mode, const msg::Vec3& position = {}) {
  msg::RobotState s;
  s.mode = mode;
  s.T_world_body.position = position;
  return s;
}

TEST(HighLevelPlanner, ALostRobotIsLeftOutAndItsClustersGoToTheOthersUntilItIsBack) {
  const msg::ViewpointClusters clusters = random_clusters(15, 3);
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  // robot 2 moving, lost at 0.5 s (the bridge's state: no pose), back at 0.8 s where it
  // started
  g_script.states = {{0.1, 1, state_of(msg::RobotState::Mode::kMoving, {10, -10, 0})},
                     {0.5, 1, state_of(msg::RobotState::Mode::kLost)},
                     {0.8, 1, state_of(msg::RobotState::Mode::kMoving, {10, -10, 0})}};
  PlanRun r = run(launch_text(kThreeGround,
                              "{name: hlp, type: high_level_planner, per_robot: false, params: "
                              "{min_replan_period_s: 100}}"));
  ASSERT_EQ(r.plans.size(), 3u);  // the clusters, robot 2 lost, robot 2 back
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().lost_replans, 2u);

  const PlanRobot r1{.id = 1, .type_bit = 1, .position = {-10, -10, 0}};
  const PlanRobot r2{.id = 2, .type_bit = 1, .position = {10, -10, 0}};
  const PlanRobot r3{.id = 3, .type_bit = 1, .position = {0, 12, 0}};
  const auto all = plan_tsga({r1, r2, r3}, plan_clusters(clusters));
  const auto without_2 = plan_tsga({r1, r3}, plan_clusters(clusters));
  ASSERT_TRUE(all && without_2);
  ASSERT_FALSE(all->robots[1].clusters.empty());

  // lost: robot 2 has an empty sequence, robots 1 and 3 share every cluster as TSGA does
  // for the two of them
  auto lost = partition(r.plans[1]);
  ASSERT_EQ(r.plans[1].sequences.size(), 3u);
  EXPECT_TRUE(lost[2].empty());
  EXPECT_TRUE(r.plans[1].sequences[1].viewpoints.empty());
  EXPECT_EQ(lost[1], without_2->robots[0].clusters);
  EXPECT_EQ(lost[3], without_2->robots[1].clusters);
  EXPECT_EQ(lost[1].size() + lost[3].size(), clusters.clusters.size());

  // back: the three-robot plan again
  auto back = partition(r.plans[2]);
  EXPECT_EQ(back[1], all->robots[0].clusters);
  EXPECT_EQ(back[2], all->robots[1].clusters);
  EXPECT_EQ(back[3], all->robots[2].clusters);
  EXPECT_EQ(partition(r.plans[0]), back);
}

TEST(HighLevelPlanner, TwoRobotsOneLostTheOtherTakesEveryCluster) {
  const msg::ViewpointClusters clusters = random_clusters(10, 21);
  const std::string two = R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [10, -10, 0, 0]})";
  for (const bool dist : {false, true}) {
    SCOPED_TRACE(dist ? "dist_tsga" : "tsga");
    g_script = {};
    g_script.clusters_topic = "/shared_clusters";
    g_script.clusters = {{0.2, clusters}};
    g_script.states = {{0.5, 1, state_of(msg::RobotState::Mode::kLost)}};
    PlanRun r = run(launch_text(
        two, dist ? "{name: hlp, type: high_level_planner, remap: {clusters: /shared_clusters}, "
                    "params: {algorithm: dist_tsga}}"
                  : "{name: hlp, type: high_level_planner, per_robot: false, remap: {clusters: "
                    "/shared_clusters}}"));
    // robot 1's latest sequence, and before the loss robot 2 had clusters of its own
    std::vector<uint32_t> mine;
    size_t plans_for_1 = 0;
    bool two_had = false;
    for (const msg::TeamPlan& p : r.plans)
      for (const msg::PathSequence& s : p.sequences) {
        if (s.robot_id == 1) {
          mine = s.cluster_ids;
          ++plans_for_1;
        }
        two_had = two_had || (s.robot_id == 2 && !s.cluster_ids.empty());
      }
    EXPECT_TRUE(two_had);
    EXPECT_EQ(plans_for_1, 2u);  // the clusters, then robot 2 lost
    EXPECT_EQ(std::set<uint32_t>(mine.begin(), mine.end()).size(), clusters.clusters.size());
    EXPECT_EQ(mine.size(), clusters.clusters.size());
    if (!dist) {
      ASSERT_EQ(r.plans.size(), 2u);
      EXPECT_TRUE(partition(r.plans[1])[2].empty());
    }
  }
}

// dist_tsga, idle_teammate_s: a teammate idle that long is planned without (its map may
// lack the clusters this robot sees), so robot 1 takes every cluster; without the rule its
// share stays with the idle robot 2.
TEST(HighLevelPlanner, DistTsgaPlansWithoutATeammateIdleTooLong) {
  const msg::ViewpointClusters clusters = random_clusters(10, 21);
  const std::string two = R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [10, -10, 0, 0]})";
  for (const double idle_s : {0.0, 5.0}) {
    SCOPED_TRACE(idle_s);
    g_script = {};
    g_script.clusters_topic = "/shared_clusters";
    g_script.clusters = {{0.2, clusters}, {7.0, clusters}};
    g_script.states = {{0.1, 1, state_of(msg::RobotState::Mode::kIdle, {10, -10, 0})}};
    PlanRun r = run(launch_text(two,
                                "{name: hlp, type: high_level_planner, remap: {clusters: "
                                "/shared_clusters}, params: {algorithm: dist_tsga, "
                                "idle_teammate_s: " +
                                    std::to_string(idle_s) + "}}",
                                7.5));
    std::vector<uint32_t> first, last;
    for (const msg::TeamPlan& p : r.plans)
      for (const msg::PathSequence& seq : p.sequences)
        if (seq.robot_id == 1) {
          if (first.empty()) first = seq.cluster_ids;
          last = seq.cluster_ids;
        }
    ASSERT_FALSE(first.empty());
    EXPECT_LT(first.size(), clusters.clusters.size()) << "robot 2 has a share at first";
    if (idle_s > 0)
      EXPECT_EQ(std::set<uint32_t>(last.begin(), last.end()).size(), clusters.clusters.size());
    else
      EXPECT_EQ(last, first);
  }
}

// --- inter_cluster_distance: roadmap ---

// One ground robot at (4, 1), left of a wall across x = 5 from y = 0 to 4.5 in a 10 × 6 m
// map (the only way past it: y > 4.5). Cluster 100 at (6, 1), 2 m away behind the wall (by
// the roadmap about 8 m, over the wall's end); cluster 101 at (1, 4), 4.2 m away in the
// open. The straight line visits 100 first, the roadmap 101.
const std::string kWallRobot = R"(
  - {id: 1, namespace: r1, kind: ground, start: [4, 1, 0, 0]})";

std::shared_ptr<const tsdf::MapSnapshot> wall_map() {
  using V3 = Eigen::Vector3d;
  motion::test::BoxWorld w(0.1, Eigen::AlignedBox3d(V3(0, 0, -0.2), V3(10, 6, 1.2)));
  w.add_box(V3(-1, -1, -0.2), V3(11, 7, 0));  // floor
  w.add_box(V3(4.8, -1, 0), V3(5.2, 4.5, 1.2));
  return w.write();
}

msg::ViewpointClusters wall_clusters() {
  msg::ViewpointClusters m;
  m.map_version = 3;
  for (const auto& [id, x, y] : {std::tuple<uint32_t, double, double>{100, 6, 1}, {101, 1, 4}}) {
    msg::ViewpointCluster c;
    c.id = id;
    c.gain = 0.1;
    c.robot_types = 3;
    msg::Viewpoint v;
    v.pose.position = {x, y, 0.35};
    v.robot_types = 3;
    c.viewpoints.push_back(v);
    c.centroid = v.pose.position;
    m.clusters.push_back(c);
  }
  return m;
}

const std::string kRoadmapPlanner =
    "{name: hlp, type: high_level_planner, per_robot: false, params: {inter_cluster_distance: "
    "roadmap, planner_seed: 1, collision_check_step_m: 0.05}}";

TEST(HighLevelPlanner, RoadmapDistancesReorderATourAroundAWall) {
  g_script = {};
  g_script.maps = {{0.1, wall_map()}};
  g_script.clusters = {{0.2, wall_clusters()}};
  PlanRun euclidean =
      run(launch_text(kWallRobot, "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(euclidean.plans.size(), 1u);
  EXPECT_EQ(euclidean.plans[0].sequences.at(0).cluster_ids, (std::vector<uint32_t>{100, 101}));

  PlanRun roadmap = run(launch_text(kWallRobot, kRoadmapPlanner));
  ASSERT_EQ(roadmap.plans.size(), 1u);
  const msg::PathSequence& s = roadmap.plans[0].sequences.at(0);
  EXPECT_EQ(s.cluster_ids, (std::vector<uint32_t>{101, 100}));
  ASSERT_EQ(s.cluster_utilities.size(), 2u);
  // f = g exp(-λ_tc d): d to 101 is the straight line (x, y: free), on to 100 around the
  // wall's end: at least hypot(4, 0.85) + hypot(1, 3.85) (the body passes y >= 4.85)
  EXPECT_NEAR(s.cluster_utilities[0], 0.1 * std::exp(-0.5 * std::hypot(3.0, 3.0)), 1e-9);
  EXPECT_LT(s.cluster_utilities[1],
            0.1 * std::exp(-0.5 * (std::hypot(4.0, 0.85) + std::hypot(1.0, 3.85))));
  EXPECT_GT(s.cluster_utilities[1], 0.1 * std::exp(-0.5 * 12.0));
  ASSERT_EQ(roadmap.planners.size(), 1u);
  const HighLevelPlanner::Stats& stats = roadmap.planners[0]->stats();
  EXPECT_GE(stats.roadmap_queries, 3u);  // the robot and both clusters' exits
  EXPECT_LE(stats.roadmap_queries, 3u);  // memoised: one row per starting point
  EXPECT_EQ(stats.straight_fallbacks, 0u);
}

TEST(HighLevelPlanner, RoadmapDistancesAreTheStraightLineUntilTheFirstMap) {
  g_script = {};
  g_script.clusters = {{0.1, wall_clusters()}, {0.5, wall_clusters()}};
  g_script.maps = {{0.3, wall_map()}};
  testing::internal::CaptureStderr();
  PlanRun r = run(launch_text(kWallRobot, kRoadmapPlanner));
  const std::string err = testing::internal::GetCapturedStderr();
  ASSERT_EQ(r.plans.size(), 2u);
  EXPECT_EQ(r.plans[0].sequences.at(0).cluster_ids, (std::vector<uint32_t>{100, 101}));
  EXPECT_EQ(r.plans[1].sequences.at(0).cluster_ids, (std::vector<uint32_t>{101, 100}));
  EXPECT_NE(err.find("no map"), std::string::npos) << err;
}

TEST(HighLevelPlanner, BadConfigurationsFailWithTheReason) {
  EXPECT_NE(config_errors(launch_text(R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: u2, kind: multirotor, start: [10, 10, 3, 0]})",
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {inter_cluster_distance: roadmap}}"))
                .find("mixed team"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {inter_cluster_distance: roadmap, "
                                      "roadmap_distance_min_vertices: -3}}"))
                .find("roadmap_distance_min_vertices"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {inter_cluster_distance: shortest}}"))
                .find("inter_cluster_distance"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {algorithm: dist_tsga}}"))
                .find("per_robot: true"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround, "{name: hlp, type: high_level_planner}"))
                .find("centralized"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {algorithm: lkh}}"))
                .find("algorithm"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {ground_lambda_tc_per_m: -1}}"))
                .find("ground_lambda_tc_per_m"),
            std::string::npos);
}

}  // namespace
}  // namespace scancrew::high_level_planner
