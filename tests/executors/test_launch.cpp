// Launch files: a good one composes and runs deterministically on sim time; every bad
// one fails with a message naming the file, the key and what is allowed, and starts
// nothing.

#include <gtest/gtest.h>

#include <algorithm>

#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "tests/executors/test_components.hpp"

namespace scancrew {
namespace {

// Keeps its string parameters, to check what the launch file handed it.
class Named final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps its label parameters";
  struct Config {
    std::string label;
    std::vector<std::string> labels;
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional("label", c.label);
    p.optional_list("labels", c.labels);
    return c;
  }
  Named(ComponentContext c, Config config) : Component(std::move(c)), config_(std::move(config)) {}
  const Config& config() const { return config_; }

 private:
  Result<void, std::string> on_configure() override { return {}; }
  Config config_;
};
SCANCREW_REGISTER_COMPONENT(Named, "test_named")

constexpr const char* kGood = R"(
clock: sim
executor: {type: step}
run: {duration_s: 1.0, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: robot1}
  - {id: 2, namespace: robot2}
components:
  - name: talker
    type: test_talker
    params: {period_s: 0.1}
    remap: {out: chatter}
  - name: listener
    type: test_listener
    remap: {in: chatter}
  - name: team_listener
    type: test_listener
    per_robot: false
    remap: {in: /robot2/chatter}
)";

std::string errors_of(const std::string& text) {
  auto launch = Launch::from_string(text, "bad.yaml");
  if (launch) return "";
  std::string all;
  for (const auto& e : launch.error()) all += e + "\n";
  return all;
}

TEST(Launch, ComposesRobotsNamespacesAndRemaps) {
  auto launch = Launch::from_string(kGood, "good.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  auto& l = **launch;
  EXPECT_EQ(l.components().size(), 5u);
  const auto names = l.graph().topic_names();
  EXPECT_EQ(names, (std::vector<std::string>{"/robot1/chatter", "/robot2/chatter"}));
  EXPECT_TRUE(l.report().errors.empty());
  EXPECT_TRUE(l.report().warnings.empty());
}

TEST(Launch, RunsDeterministicallyOnSimTime) {
  std::vector<uint64_t> received;
  for (int run = 0; run < 2; ++run) {
    auto launch = Launch::from_string(kGood, "good.yaml");
    ASSERT_TRUE(launch);
    const double ran = (*launch)->run();
    EXPECT_DOUBLE_EQ(ran, 1.0);
    const auto stats = (*launch)->graph().stats();
    for (const auto& s : stats) received.push_back(s.taken);
  }
  // 1 s of sim time, a 0.1 s timer: 10 messages per robot; robot2's go to two readers
  EXPECT_EQ(received, (std::vector<uint64_t>{10, 20, 10, 20}));
}

TEST(Launch, UnknownComponentTypeListsTheRegisteredOnes) {
  const std::string e = errors_of(R"(
components:
  - {name: a, type: test_talkr}
)");
  EXPECT_NE(e.find("bad.yaml:3: components[0].type: unknown component 'test_talkr'; registered:"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("test_talker"), std::string::npos) << e;
}

TEST(Launch, MissingParameterNamesTheKey) {
  const std::string e = errors_of("components:\n  - {name: a, type: test_talker}\n");
  EXPECT_NE(e.find("components[0].params.period_s: missing required parameter; allowed: a number "
                   "in [1e-06, 100]"),
            std::string::npos)
      << e;
}

TEST(Launch, MistypedAndOutOfRangeParametersNameTheKeyAndTheRange) {
  const std::string e = errors_of(R"(
components:
  - name: a
    type: test_talker
    params:
      period_s: 1000
      start: minus one
)");
  EXPECT_NE(e.find("bad.yaml:6: components[0].params.period_s: 1000 is out of range; allowed: a "
                   "number in [1e-06, 100]"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("bad.yaml:7: components[0].params.start: 'minus one' has the wrong type"),
            std::string::npos)
      << e;
}

TEST(Launch, UnknownKeysAreErrors) {
  const std::string e = errors_of(R"(
executor: {type: multi_threaded, thread: 2}
components:
  - {name: a, type: test_talker, params: {period_s: 1}, remapp: {}}
)");
  EXPECT_NE(e.find("bad.yaml:2: executor.thread: unknown parameter; known: type, threads, spin_us"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("bad.yaml:4: components[0].remapp: unknown key; allowed: name, type"),
            std::string::npos)
      << e;
}

// Two components of one name were both composed (Step 12's review); two keys of one name in
// a mapping kept the first silently.
TEST(Launch, DuplicateComponentNamesAndKeysAreErrors) {
  const std::string names = errors_of(R"(
components:
  - {name: a, type: test_talker, params: {period_s: 1}}
  - {name: a, type: test_talker, params: {period_s: 2}}
)");
  EXPECT_NE(names.find("bad.yaml:4: components[1].name: 'a' names components[0] too"),
            std::string::npos)
      << names;
  const std::string keys = errors_of(R"(
components:
  - {name: a, type: test_talker, params: {period_s: 1, period_s: 2}}
)");
  EXPECT_NE(keys.find("duplicate key 'period_s'"), std::string::npos) << keys;
}

// A component without a name: is named by its type (one instance of it in the file):
// composed, and found by --set, under the type's name.
TEST(Launch, AComponentWithoutANameIsNamedByItsType) {
  const std::string text = R"(
clock: sim
executor: {type: step}
robots:
  - {id: 1, namespace: r1}
components:
  - {type: test_named, params: {label: "from file"}}
  - {name: other, type: test_named, per_robot: false}
)";
  auto launch = Launch::from_string(text, "typed.yaml", {.overrides = {"test_named.label=set"}});
  ASSERT_TRUE(launch) << launch.error().front();
  std::vector<std::string> got;
  for (const auto& c : (*launch)->components()) {
    got.push_back(c->qualified_name());
    if (const auto* n = dynamic_cast<const Named*>(c.get())) got.push_back(n->config().label);
  }
  EXPECT_EQ(got, (std::vector<std::string>{"/r1/test_named", "set", "/other", ""}));
}

// Two components of one type, neither named (or one named as the other's type): one name
// for two, refused naming the name.
TEST(Launch, TwoUnnamedComponentsOfOneTypeAreRefused) {
  const std::string both = errors_of(R"(
components:
  - {type: test_talker, params: {period_s: 1}}
  - {type: test_talker, params: {period_s: 2}}
)");
  EXPECT_NE(both.find("bad.yaml:4: components[1] (no name: its type's): 'test_talker' names "
                      "components[0] too; each component has a name of its own (two components "
                      "of one type need distinct name: keys)"),
            std::string::npos)
      << both;
  const std::string one = errors_of(R"(
components:
  - {type: test_talker, params: {period_s: 1}}
  - {name: test_talker, type: test_named}
)");
  EXPECT_NE(one.find("bad.yaml:4: components[1].name: 'test_talker' names components[0] too"),
            std::string::npos)
      << one;
  // distinct names: two of one type compose
  EXPECT_EQ(errors_of(R"(
clock: sim
executor: {type: step}
components:
  - {type: test_talker, per_robot: false, params: {period_s: 1}}
  - {name: second_talker, type: test_talker, per_robot: false, params: {period_s: 2}}
)"),
            "");
}

TEST(Launch, UnknownParameterIsAnError) {
  const std::string e = errors_of(
      "components:\n  - {name: a, type: test_talker, params: {period_s: 1, perod_s: 2}}\n");
  EXPECT_NE(
      e.find("bad.yaml:2: components[0].params.perod_s: unknown parameter; known: period_s, start"),
      std::string::npos)
      << e;
}

TEST(Launch, TopicTypeMismatchNamesBothEndsAndStartsNothing) {
  const int activated_before = test::Listener::activated.load();
  const std::string e = errors_of(R"(
components:
  - {name: talker, type: test_talker, params: {period_s: 1}, remap: {out: chatter}}
  - {name: blobs, type: test_blob_listener, remap: {in: chatter}}
  - {name: listener, type: test_listener, remap: {in: chatter}}
)");
  EXPECT_NE(e.find("topic type mismatch on '/chatter': it carries 'scancrew/test/Counter' (used by "
                   "/talker.out)"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("wants 'scancrew/test/Blob'"), std::string::npos) << e;
  EXPECT_EQ(test::Listener::activated.load(), activated_before);
}

TEST(Launch, RemapToNothingIsAnError) {
  const std::string e = errors_of(R"(
components:
  - {name: talker, type: test_talker, params: {period_s: 1}, remap: {out: ""}}
  - {name: listener, type: test_listener, remap: {in: ~}}
)");
  EXPECT_NE(e.find("components[0].remap.out: remap to nothing"), std::string::npos) << e;
  EXPECT_NE(e.find("components[1].remap.in: remap to nothing"), std::string::npos) << e;
}

TEST(Launch, RemapOfAPortTheComponentDoesNotHaveIsAnError) {
  const std::string e = errors_of(R"(
components:
  - {name: talker, type: test_talker, params: {period_s: 1}, remap: {output: chatter}}
)");
  EXPECT_NE(e.find("components[0].remap.output: component 'test_talker' has no port 'output'; its "
                   "ports: out"),
            std::string::npos)
      << e;
}

TEST(Launch, ALaunchRemapOfAPortNoComponentHasIsWarnedAbout) {
  // the launch's own remap serves every component with the port; "outt" is nobody's
  testing::internal::CaptureStderr();
  auto launch = Launch::from_string(R"(
remap: {outt: chatter}
components:
  - {name: talker, type: test_talker, params: {period_s: 1}}
)",
                                    "typo.yaml");
  const std::string log = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(launch);
  EXPECT_NE(log.find("typo.yaml: remap.outt: no component has port 'outt'"), std::string::npos)
      << log;
  testing::internal::CaptureStderr();
  auto used = Launch::from_string(R"(
remap: {out: chatter}
components:
  - {name: talker, type: test_talker, params: {period_s: 1}}
)",
                                  "used.yaml");
  EXPECT_TRUE(used);
  EXPECT_EQ(testing::internal::GetCapturedStderr().find("remap.out"), std::string::npos);
}

TEST(Launch, StepExecutorNeedsTheSimClock) {
  const std::string e = errors_of(R"(
clock: wall
executor: {type: step}
components:
  - {name: talker, type: test_talker, params: {period_s: 1}}
)");
  EXPECT_NE(e.find("executor.type: 'step' runs on sim time; allowed with clock: sim only"),
            std::string::npos)
      << e;
}

TEST(Launch, BadValuesInTheTopLevelSectionsAreNamed) {
  const std::string e = errors_of(R"(
clock: lunar
executor: {type: multi_threaded, threads: 0}
robots:
  - {id: 1, namespace: r1}
  - {id: 1, namespace: "r 2"}
components:
  - {name: talker, type: test_talker, params: {period_s: 1}}
)");
  EXPECT_NE(e.find("(top level).clock: 'lunar' is not allowed; allowed: wall, sim"),
            std::string::npos)
      << e;
  EXPECT_NE(
      e.find("executor.threads: 0 is out of range; allowed: a non-negative integer in [1, 64]"),
      std::string::npos)
      << e;
  EXPECT_NE(e.find("robots[1].id: 1 is used twice"), std::string::npos) << e;
  EXPECT_NE(e.find("robots[1].namespace: 'r 2' is not a name"), std::string::npos) << e;
}

TEST(Launch, NothingIsConstructedWhenTheFileHasStructuralErrors) {
  const int before = test::Talker::constructed.load();
  const std::string e = errors_of(R"(
components:
  - {name: talker, type: test_talker, params: {period_s: 1}}
  - {name: other, type: no_such_component}
)");
  EXPECT_FALSE(e.empty());
  EXPECT_EQ(test::Talker::constructed.load(), before);
}

TEST(Launch, UnreadableFileIsAnError) {
  auto launch = Launch::from_file("/nonexistent/launch.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("cannot read the launch file: no such file"),
            std::string::npos)
      << launch.error().front();
}

TEST(Launch, UnconnectedInputIsAWarning) {
  auto launch = Launch::from_string("components:\n  - {name: l, type: test_listener}\n", "w.yaml");
  ASSERT_TRUE(launch);
  const auto report = (*launch)->report();
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("unconnected input: /l.in reads '/in'"), std::string::npos);
}

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
