// Launch options and what a launch file composes: a multi-threaded run on the wall clock,
// per-robot parameter substitution ({ns}, {id}, {out}), the process: key, --set overrides,
// the station's components on the one robot, and the robot count (--robots, run.robots).

#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "executors/launch.hpp"
#include "tests/executors/launch_harness.hpp"
#include "tests/executors/test_components.hpp"

namespace scancrew {
namespace {

using test::errors_of;
using test::Named;

TEST(Launch, MultiThreadedWallClockRunStopsAtItsDuration) {
  auto launch = Launch::from_string(R"(
clock: wall
executor: {type: multi_threaded, threads: 2}
run: {duration_s: 0.3}
components:
  - {name: talker, type: test_talker, params: {period_s: 0.01}, remap: {out: c}}
  - {name: listener, type: test_listener, remap: {in: c}}
)",
                                    "wall.yaml");
  ASSERT_TRUE(launch);
  const double ran = (*launch)->run();
  EXPECT_GE(ran, 0.3);
  EXPECT_LT(ran, 5.0);
  EXPECT_GT((*launch)->graph().stats().front().taken, 0u);
}

TEST(Launch, PerRobotParametersNameTheirRobot) {
  auto launch = Launch::from_string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 0.1, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1}
  - {id: 7, namespace: scout}
components:
  - {name: per, type: test_named, params: {label: "/tmp/mesh_{ns}_{id}.ply", labels: ["{ns}", "x{id}{id}"]}}
  - {name: one, type: test_named, per_robot: false, params: {label: "/tmp/{ns}.ply"}}
)",
                                    "named.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  std::vector<std::string> labels;
  for (const auto& c : (*launch)->components())
    if (const auto* n = dynamic_cast<const Named*>(c.get())) {
      labels.push_back(n->config().label);
      for (const std::string& l : n->config().labels) labels.push_back(l);
    }
  // per robot: substituted; a station component has no robot: left as written
  EXPECT_EQ(labels,
            (std::vector<std::string>{"/tmp/mesh_r1_1.ply", "r1", "x11", "/tmp/mesh_scout_7.ply",
                                      "scout", "x77", "/tmp/{ns}.ply"}));
}

// A team split over processes: each command composes the components its process: key
// lists; a robot process makes its own robot's per-robot components.
TEST(Launch, EachProcessComposesTheComponentsItsProcessKeyLists) {
  const std::string text = R"(
clock: sim
executor: {type: step}
run: {duration_s: 0.1, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1}
  - {id: 2, namespace: r2}
components:
  - {name: sim, type: test_named, per_robot: false, process: [run, sim]}
  - {name: brain, type: test_named}
  - {name: watch_all, type: test_named, per_robot: false, process: run}
  - {name: watch_sim, type: test_named, per_robot: false, process: sim}
  - {name: link, type: test_named, process: robot}
)";
  const auto names = [&](const LaunchOptions& options) {
    auto launch = Launch::from_string(text, "team.yaml", options);
    std::vector<std::string> out;
    if (!launch) return std::vector<std::string>{"error: " + launch.error().front()};
    for (const auto& c : (*launch)->components()) out.push_back(c->qualified_name());
    return out;
  };
  EXPECT_EQ(names({}), (std::vector<std::string>{"/sim", "/r1/brain", "/r2/brain", "/watch_all"}));
  EXPECT_EQ(names({.process = "sim"}), (std::vector<std::string>{"/sim", "/watch_sim"}));
  EXPECT_EQ(names({.process = "robot", .robot_id = 2}),
            (std::vector<std::string>{"/r2/brain", "/r2/link"}));
  EXPECT_NE(names({.process = "robot", .robot_id = 3}).front().find("--robot 3: no such robot"),
            std::string::npos);
  EXPECT_NE(names({.process = "station"}).front().find("no component runs in the 'station'"),
            std::string::npos);
  EXPECT_NE(errors_of(R"(
components:
  - {name: a, type: test_named, process: [sim, moon]}
)")
                .find("'moon' is no process; allowed: run, sim, robot, station"),
            std::string::npos);
}

TEST(Launch, OutDirectoryIsSubstitutedForEveryComponent) {
  const std::string text = R"(
clock: sim
executor: {type: step}
robots:
  - {id: 1, namespace: r1}
components:
  - {name: per, type: test_named, params: {label: "{out}/mesh_{ns}.ply"}}
  - {name: one, type: test_named, per_robot: false, params: {label: "{out}/paths.csv"}}
)";
  auto labels_of = [](const Launch& launch) {
    std::vector<std::string> labels;
    for (const auto& c : launch.components())
      if (const auto* n = dynamic_cast<const Named*>(c.get())) labels.push_back(n->config().label);
    return labels;
  };
  auto given = Launch::from_string(text, "cfg/arena_team.yaml", {.out_dir = "/data/run7"});
  ASSERT_TRUE(given) << given.error().front();
  EXPECT_EQ((*given)->out_dir(), "/data/run7");
  EXPECT_EQ(labels_of(**given),
            (std::vector<std::string>{"/data/run7/mesh_r1.ply", "/data/run7/paths.csv"}));
  // no --out: runs/<launch file stem>
  auto defaulted = Launch::from_string(text, "cfg/arena_team.yaml");
  ASSERT_TRUE(defaulted);
  EXPECT_EQ(labels_of(**defaulted),
            (std::vector<std::string>{"runs/arena_team/mesh_r1.ply", "runs/arena_team/paths.csv"}));
}

// A relative input path is relative to the launch file's directory, one given with --set to
// the working directory, an absolute one is kept (Component::input_path); a launch without a
// directory (a label) reads from the working directory
TEST(Launch, InputPathsAreTheLaunchFilesButSetOnesTheWorkingDirectorys) {
  const std::string text = R"(
components:
  - {name: a, type: test_named, params: {label: ../scenes/x.yaml}}
  - {name: b, type: test_named, params: {label: scenes/x.yaml}}
  - {name: c, type: test_named, params: {label: /abs/x.yaml}}
)";
  const auto paths_of = [](const Launch& launch) {
    std::vector<std::string> paths;
    for (const auto& c : launch.components())
      if (const auto* n = dynamic_cast<const Named*>(c.get())) paths.push_back(n->label_path());
    return paths;
  };
  auto in_dir =
      Launch::from_string(text, "cfg/missions/m.yaml", {.overrides = {"b.label=my/x.yaml"}});
  ASSERT_TRUE(in_dir) << in_dir.error().front();
  EXPECT_EQ(paths_of(**in_dir),
            (std::vector<std::string>{"cfg/scenes/x.yaml", "my/x.yaml", "/abs/x.yaml"}));
  auto no_dir = Launch::from_string(text, "m.yaml");
  ASSERT_TRUE(no_dir) << no_dir.error().front();
  EXPECT_EQ(paths_of(**no_dir),
            (std::vector<std::string>{"../scenes/x.yaml", "scenes/x.yaml", "/abs/x.yaml"}));
}

TEST(Launch, SetOverridesAComponentParameterOrARunSetting) {
  const std::string text = R"(
clock: sim
executor: {type: step}
run: {duration_s: 5}
components:
  - {name: a, type: test_named, per_robot: false, params: {label: "from file"}}
  - {name: b, type: test_named, per_robot: false}
)";
  auto launch = Launch::from_string(
      text, "set.yaml",
      {.overrides = {"a.label=overridden", "b.labels=[x, y]", "run.duration_s=2.5"}});
  ASSERT_TRUE(launch) << launch.error().front();
  EXPECT_DOUBLE_EQ((*launch)->settings().duration_s, 2.5);
  std::vector<std::string> got;
  for (const auto& c : (*launch)->components())
    if (const auto* n = dynamic_cast<const Named*>(c.get())) {
      got.push_back(n->config().label);
      for (const std::string& l : n->config().labels) got.push_back(l);
    }
  EXPECT_EQ(got, (std::vector<std::string>{"overridden", "", "x", "y"}));
}

TEST(Launch, BadSetIsRefusedNamingItAndWhatIsAllowed) {
  const std::string text = R"(
clock: sim
executor: {type: step}
components:
  - {name: a, type: test_named, per_robot: false}
)";
  auto no_component = Launch::from_string(text, "set.yaml", {.overrides = {"nobody.label=x"}});
  ASSERT_FALSE(no_component);
  EXPECT_NE(no_component.error().front().find("no component named 'nobody'"), std::string::npos);
  auto no_equals = Launch::from_string(text, "set.yaml", {.overrides = {"a.label"}});
  ASSERT_FALSE(no_equals);
  EXPECT_NE(no_equals.error().front().find("expected name.key=value"), std::string::npos);
  // the value goes through the component's own checks: an unknown key is still refused
  auto unknown = Launch::from_string(text, "set.yaml", {.overrides = {"a.colour=red"}});
  ASSERT_FALSE(unknown);
  bool named = false;
  for (const auto& e : unknown.error()) named = named || e.find("colour") != std::string::npos;
  EXPECT_TRUE(named);
  auto out_of_range = Launch::from_string(text, "set.yaml", {.overrides = {"run.duration_s=-1"}});
  EXPECT_FALSE(out_of_range);
}

// --set clock=wall: a sim-time launch (as a mission composes it) runs on the wall clock, on a
// multi-threaded executor with a thread per core, without its sim-time run: keys.
TEST(Launch, SetClockWallRunsASimLaunchOnTheWallClockMultiThreaded) {
  const std::string text = R"(
clock: sim
executor: {type: step}
run: {duration_s: 5, sim_step_s: 0.05, compute_time: charged, real_time_factor: 2}
components:
  - {name: a, type: test_named, per_robot: false}
)";
  auto launch = Launch::from_string(text, "wall.yaml", {.overrides = {"clock=wall"}});
  ASSERT_TRUE(launch) << launch.error().front();
  const LaunchSettings& s = (*launch)->settings();
  EXPECT_EQ(s.clock, ClockType::kWall);
  EXPECT_EQ(s.executor, LaunchSettings::ExecutorType::kMultiThreaded);
  EXPECT_EQ(s.threads, std::max(1u, std::thread::hardware_concurrency()));
  EXPECT_DOUBLE_EQ(s.duration_s, 5.0);            // kept: now wall seconds
  EXPECT_TRUE((*launch)->place_stats().empty());  // compute is not charged
  // the file's own threaded executor is kept
  std::string threaded = text;
  threaded.replace(threaded.find("{type: step}"), 12, "{type: single_threaded}");
  launch = Launch::from_string(threaded, "wall.yaml", {.overrides = {"clock=wall"}});
  ASSERT_TRUE(launch) << launch.error().front();
  EXPECT_EQ((*launch)->settings().executor, LaunchSettings::ExecutorType::kSingleThreaded);
}

TEST(Launch, SetClockWallRefusesSimTimeSettingsNamingThem) {
  const std::string text = R"(
clock: sim
executor: {type: step}
components:
  - {name: a, type: test_named, per_robot: false}
)";
  for (const char* contradiction : {"run.compute_time=charged", "run.compute_time=free",
                                    "run.real_time_factor=1", "executor.type=step"}) {
    auto launch =
        Launch::from_string(text, "wall.yaml", {.overrides = {"clock=wall", contradiction}});
    ASSERT_FALSE(launch) << contradiction;
    EXPECT_NE(launch.error().front().find(
                  std::string("--set clock=wall contradicts --set ") +
                  std::string(contradiction).substr(0, std::string(contradiction).find('='))),
              std::string::npos)
        << launch.error().front();
  }
  auto bad = Launch::from_string(text, "wall.yaml", {.overrides = {"clock=steady"}});
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().front().find("clock is 'wall' or 'sim'"), std::string::npos);
}

// Which computer each component runs on (docs/runtime.md, "Compute-charged time").
std::vector<std::string> place_names(const Launch& launch) {
  std::vector<std::string> names;
  for (const PlaceStats& p : launch.place_stats()) names.push_back(p.name);
  std::sort(names.begin(), names.end());
  return names;
}

TEST(Launch, WithoutAStationTheOneRobotRunsTheStationsComponents) {
  const std::string one_robot = R"(
clock: sim
executor: {type: step}
run: {duration_s: 0.1, sim_step_s: 0.05, compute_time: charged%s}
robots:
  - {id: 1, namespace: r1}
components:
  - {name: per, type: test_named}
  - {name: shared, type: test_named, per_robot: false}
)";
  const auto with_run = [](std::string text, const std::string& run_extra) {
    return text.replace(text.find("%s"), 2, run_extra);
  };
  auto with_station = Launch::from_string(with_run(one_robot, ""), "one.yaml");
  ASSERT_TRUE(with_station) << with_station.error().front();
  EXPECT_EQ(place_names(**with_station), (std::vector<std::string>{"r1", "station"}));
  auto on_board = Launch::from_string(with_run(one_robot, ", station: false"), "one.yaml");
  ASSERT_TRUE(on_board) << on_board.error().front();
  EXPECT_EQ(place_names(**on_board), (std::vector<std::string>{"r1"}));
  // a team has no "one robot" to put them on
  std::string team = with_run(one_robot, ", station: false");
  team.replace(team.find("components:"), 0, "  - {id: 2, namespace: r2}\n");
  auto refused = Launch::from_string(team, "team.yaml");
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().front().find("run.station: false"), std::string::npos)
      << refused.error().front();
}

// the labels of the per-robot test_named instances: "{ns}" of each robot that runs
std::vector<std::string> robots_run(const Launch& launch) {
  std::vector<std::string> names;
  for (const auto& c : launch.components())
    if (const auto* n = dynamic_cast<const Named*>(c.get())) names.push_back(n->config().label);
  return names;
}

constexpr const char* kThreeRobots = R"(
clock: sim
executor: {type: step}
run: {duration_s: 0.1, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1}
  - {id: 2, namespace: r2}
  - {id: 3, namespace: r3}
components:
  - {name: per, type: test_named, params: {label: "{ns}"}}
)";

TEST(Launch, RobotCountRunsTheFirstRobotsOfTheList) {
  auto all = Launch::from_string(kThreeRobots, "team.yaml");
  ASSERT_TRUE(all) << all.error().front();
  EXPECT_EQ(robots_run(**all), (std::vector<std::string>{"r1", "r2", "r3"}));
  auto two = Launch::from_string(kThreeRobots, "team.yaml", {.robot_count = 2});
  ASSERT_TRUE(two) << two.error().front();
  EXPECT_EQ(robots_run(**two), (std::vector<std::string>{"r1", "r2"}));
  auto one = Launch::from_string(kThreeRobots, "team.yaml", {.robot_count = 1});
  ASSERT_TRUE(one) << one.error().front();
  EXPECT_EQ(robots_run(**one), (std::vector<std::string>{"r1"}));
  auto three = Launch::from_string(kThreeRobots, "team.yaml", {.robot_count = 3});
  ASSERT_TRUE(three) << three.error().front();
  EXPECT_EQ(robots_run(**three), (std::vector<std::string>{"r1", "r2", "r3"}));
}

TEST(Launch, MoreRobotsThanListedIsRefusedNamingBothNumbers) {
  auto four = Launch::from_string(kThreeRobots, "team.yaml", {.robot_count = 4});
  ASSERT_FALSE(four);
  ASSERT_EQ(four.error().size(), 1u);
  EXPECT_NE(four.error().front().find("team.yaml:6: robots: 4 robots asked for (--robots), but "
                                      "the file lists 3"),
            std::string::npos)
      << four.error().front();
  // without a robots: list a launch file has one robot
  auto no_list = Launch::from_string(R"(
clock: sim
executor: {type: step}
components:
  - {name: per, type: test_named, params: {label: "{ns}"}}
)",
                                     "alone.yaml", {.robot_count = 2});
  ASSERT_FALSE(no_list);
  EXPECT_NE(no_list.error().front().find("2 robots asked for (--robots), but the file lists 1"),
            std::string::npos)
      << no_list.error().front();
  auto one = Launch::from_string(R"(
clock: sim
executor: {type: step}
components:
  - {name: per, type: test_named, params: {label: "x"}}
)",
                                 "alone.yaml", {.robot_count = 1});
  EXPECT_TRUE(one);
}

TEST(Launch, RunRobotsIsTheFilesOwnCountAndRobotCountOverridesIt) {
  const std::string text = kThreeRobots;
  auto with_default = Launch::from_string(text, "team.yaml", {.overrides = {"run.robots=2"}});
  ASSERT_TRUE(with_default) << with_default.error().front();
  EXPECT_EQ((*with_default)->settings().robots, 2u);
  EXPECT_EQ(robots_run(**with_default), (std::vector<std::string>{"r1", "r2"}));
  auto overridden =
      Launch::from_string(text, "team.yaml", {.overrides = {"run.robots=2"}, .robot_count = 3});
  ASSERT_TRUE(overridden) << overridden.error().front();
  EXPECT_EQ(robots_run(**overridden), (std::vector<std::string>{"r1", "r2", "r3"}));
  auto too_many = Launch::from_string(text, "team.yaml", {.overrides = {"run.robots=5"}});
  ASSERT_FALSE(too_many);
  EXPECT_NE(too_many.error().front().find("run.robots: 5 robots asked for, but the file lists 3"),
            std::string::npos)
      << too_many.error().front();
}

}  // namespace
}  // namespace scancrew
