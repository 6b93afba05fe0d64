#include <gtest/gtest.h>

#include "executors/component.hpp"
#include "executors/step_executor.hpp"
#include "tests/executors/test_components.hpp"

namespace scancrew {
namespace {

using test::Listener;
using test::Talker;

ComponentContext context_for(Graph& graph, const std::string& name,
                             std::map<std::string, std::string> remaps = {}) {
  ComponentContext c;
  c.graph = &graph;
  c.name = name;
  c.ns = "robot1";
  c.robot_id = 1;
  c.remaps = std::move(remaps);
  return c;
}

TEST(Lifecycle, FollowsConfigureActivateDeactivateShutdown) {
  Graph graph(std::make_shared<SimClock>());
  Talker talker(context_for(graph, "talker"), {.period_s = 0.01});
  EXPECT_EQ(talker.state(), LifecycleState::kUnconfigured);
  EXPECT_FALSE(talker.activate());  // not configured yet
  ASSERT_TRUE(talker.configure());
  EXPECT_EQ(talker.state(), LifecycleState::kInactive);
  EXPECT_FALSE(talker.configure());  // twice
  ASSERT_TRUE(talker.activate());
  EXPECT_EQ(talker.state(), LifecycleState::kActive);
  EXPECT_FALSE(talker.activate());
  ASSERT_TRUE(talker.deactivate());
  EXPECT_EQ(talker.state(), LifecycleState::kInactive);
  ASSERT_TRUE(talker.activate());
  ASSERT_TRUE(talker.shutdown());  // from active: deactivates first
  EXPECT_EQ(talker.state(), LifecycleState::kFinalized);
  auto again = talker.shutdown();
  ASSERT_FALSE(again);
  EXPECT_NE(again.error().find("finalized"), std::string::npos);
}

TEST(Lifecycle, OnlyActiveComponentsRunCallbacks) {
  auto clock = std::make_shared<SimClock>();
  Graph graph(clock);
  Talker talker(context_for(graph, "talker", {{"out", "chatter"}}), {.period_s = 0.01});
  Listener listener(context_for(graph, "listener", {{"in", "chatter"}}), {});
  ASSERT_TRUE(talker.configure());
  ASSERT_TRUE(listener.configure());
  StepExecutor executor(*clock);
  for (Component* c : std::initializer_list<Component*>{&talker, &listener})
    for (Executable* e : c->executables()) executor.add(*e);

  executor.run_until(100'000'000);  // both inactive: nothing happens
  EXPECT_EQ(listener.received(), 0u);
  EXPECT_EQ(graph.find("/robot1/chatter")->stats().published, 0u);

  ASSERT_TRUE(talker.activate());  // talker runs, listener's queue fills (depth 8)
  executor.run_until(200'000'000);
  EXPECT_EQ(listener.received(), 0u);
  ASSERT_TRUE(listener.activate());
  executor.run_until(200'000'000);  // queued samples are delivered now
  EXPECT_EQ(listener.received(), 8u);
  executor.run_until(300'000'000);
  EXPECT_EQ(listener.received(), 18u);
  EXPECT_EQ(listener.last_value(), 20u);

  ASSERT_TRUE(talker.deactivate());
  executor.run_until(400'000'000);
  EXPECT_EQ(listener.received(), 18u);
  for (Component* c : std::initializer_list<Component*>{&talker, &listener})
    for (Executable* e : c->executables()) executor.remove(*e);
}

TEST(Lifecycle, InactivePublisherRefusesToPublish) {
  Graph graph(std::make_shared<SimClock>());
  // a component that exposes its publisher
  struct Exposed : Component {
    explicit Exposed(ComponentContext c) : Component(std::move(c)) {}
    Result<void, std::string> on_configure() override {
      pub = create_publisher<test::Counter>("out");
      return {};
    }
    Publisher<test::Counter> pub;
  } exposed(context_for(graph, "exposed"));
  ASSERT_TRUE(exposed.configure());
  auto refused = exposed.pub.publish(std::move(*exposed.pub.loan()));
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error(), PublishError::kInactive);
  ASSERT_TRUE(exposed.activate());
  EXPECT_TRUE(exposed.pub.publish(std::move(*exposed.pub.loan())));
}

TEST(Lifecycle, TopicsResolveThroughRemapsAndNamespaces) {
  Graph graph(std::make_shared<SimClock>());
  Talker talker(context_for(graph, "talker", {{"out", "/team/chatter"}}), {.period_s = 1});
  Listener listener(context_for(graph, "listener"), {});
  EXPECT_EQ(talker.resolve("out"), "/team/chatter");
  EXPECT_EQ(listener.resolve("in"), "/robot1/in");
  EXPECT_EQ(talker.qualified_name(), "/robot1/talker");
  // a teammate's port: the remap, in the teammate's namespace; absolute stays
  Listener remapped(context_for(graph, "remapped", {{"in", "odom"}}), {});
  EXPECT_EQ(remapped.resolve_in("in", "robot2"), "/robot2/odom");
  EXPECT_EQ(listener.resolve_in("in", "robot2"), "/robot2/in");
  EXPECT_EQ(talker.resolve_in("out", "robot2"), "/team/chatter");
}

}  // namespace
}  // namespace scancrew
