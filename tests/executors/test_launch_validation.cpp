// Launch files: a good one composes and runs deterministically on sim time; every bad
// one fails with a message naming the file, the key and what is allowed, and starts
// nothing.

#include <gtest/gtest.h>

#include <memory>

#include "executors/clock.hpp"
#include "executors/graph.hpp"
#include "executors/launch.hpp"
#include "tests/executors/launch_harness.hpp"
#include "tests/executors/test_components.hpp"

namespace scancrew {
namespace {

using test::errors_of;
using test::Named;

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

// An input its component does without (mark_input_optional) is a note, not a warning: a
// shipped mission that lacks it (a replay without planners) is quiet.
TEST(Launch, UnconnectedOptionalInputIsANote) {
  Graph graph(std::make_shared<SimClock>());
  graph.record({.kind = EndpointInfo::Kind::kSubscription,
                .component = "/m",
                .port = "state",
                .topic = "/state",
                .type_name = "t"});
  graph.record({.kind = EndpointInfo::Kind::kSubscription,
                .component = "/m",
                .port = "depth",
                .topic = "/depth",
                .type_name = "t"});
  graph.mark_optional("/m", "state");
  const GraphReport report = graph.check();
  ASSERT_EQ(report.notes.size(), 1u);
  EXPECT_NE(report.notes[0].find("/m.state reads '/state'"), std::string::npos);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("/m.depth reads '/depth'"), std::string::npos);
  ASSERT_EQ(report.unconnected_inputs.size(), 1u);
  EXPECT_EQ(report.unconnected_inputs[0].port, "depth");
}

}  // namespace
}  // namespace scancrew
