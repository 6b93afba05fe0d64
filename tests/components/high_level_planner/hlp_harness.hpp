#pragma once

// The high_level_planner tests' harness: a scripted feeder component publishing clusters,
// ISEs, maps, robot states and replan requests at chosen sim times (g_script, set by each
// test before its launch runs), a log keeping every plan, random clusters, and the launch
// text around a planner. The components are registered in hlp_harness.cpp.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "components/high_level_planner/high_level_planner.hpp"
#include "executors/launch.hpp"
#include "interfaces/map_update.hpp"

namespace scancrew::high_level_planner::test {

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
extern Script g_script;  // NOLINT: set by each test before its launch runs

// Random clusters in a 30 m square, 1-4 viewpoints each; every viewpoint sees two ISEs.
msg::ViewpointClusters random_clusters(size_t n, uint64_t seed, uint32_t types = 3);

msg::IseSet ises_for(const msg::ViewpointClusters& clusters);

std::vector<PlanCluster> plan_clusters(const msg::ViewpointClusters& m);

inline const std::string kThreeGround = R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [10, -10, 0, 0]}
  - {id: 3, namespace: r3, kind: ground, start: [0, 12, 0, 0]})";

std::string launch_text(const std::string& robots, const std::string& planner,
                        double duration_s = 1.0);

struct PlanRun {
  std::unique_ptr<Launch> launch;
  std::vector<msg::TeamPlan> plans;
  std::vector<HighLevelPlanner*> planners;
};

PlanRun run(const std::string& text);

std::string config_errors(const std::string& text);

// robot id -> its clusters, from a plan's sequences
std::map<uint32_t, std::vector<uint32_t>> partition(const msg::TeamPlan& plan);

}  // namespace scancrew::high_level_planner::test
