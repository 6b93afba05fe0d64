// The dds_bridge's configuration: bad keys, placeholders and loops fail at start, naming the
// key; team placeholders expand over the launch's robots.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "components/dds_bridge/dds_bridge.hpp"
#include "executors/launch.hpp"

namespace scancrew::dds_bridge {
namespace {

// Every error of a launch file, joined.
std::string launch_errors(const std::string& params) {
  auto launch = Launch::from_string(
      "components:\n  - {name: bridge, type: dds_bridge, params: {" + params + "}}\n", "bad.yaml");
  if (launch) return "";
  std::string all;
  for (const auto& e : launch.error()) all += e + "\n";
  return all;
}

TEST(DdsBridge, BadConfigurationFailsAtStartNamingTheKey) {
  EXPECT_NE(launch_errors("import_topics: [plan]").find("type_plan"), std::string::npos)
      << "a topic whose type nobody gives";
  const std::string e = launch_errors(
      "import_topics: [plan, plan, 'bad name'], type_plan: scancrew/TeamPlan, qos_plan: fast, "
      "link_loss_rate: 1.5, link_partition: ['1 x'], transport: carrier_pigeon, depth_nope: 3");
  for (const char* key : {"is listed twice", "'bad name'", "qos_plan", "link_loss_rate",
                          "link_partition", "transport", "depth_nope"})
    EXPECT_NE(e.find(key), std::string::npos) << key << " in:\n" << e;
  EXPECT_NE(launch_errors("").find("nothing to bridge"), std::string::npos);
  EXPECT_NE(
      launch_errors("import_topics: [plan], type_plan: scancrew/Nope").find("not a wire message"),
      std::string::npos);
}

// Placeholders expand over the launch's team; an absolute import lands on its own name.
TEST(DdsBridge, TeamPlaceholdersExpandOverTheLaunchsRobots) {
  auto launch = Launch::from_string(R"(
clock: sim
executor: {type: step}
robots:
  - {id: 1, namespace: r1}
  - {id: 2, namespace: r2}
  - {id: 3, namespace: r3}
components:
  - name: bridge
    type: dds_bridge
    params:
      intraprocess: false
      export_topics: ["/{self}/robot_state"]
      import_topics: ["/{others}/robot_state", "/{team}/mission"]
      type_self_robot_state: scancrew/RobotState
      type_others_robot_state: scancrew/RobotState
      type_team_mission: scancrew/MissionStatus
      qos_others_robot_state: best_effort
      lost_port: "/{lost}/robot_state"
      link_loss_topics: ["/{team}/mission"]
)",
                                    "team.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  std::vector<std::string> r2;
  for (const auto& c : (*launch)->components())
    if (const auto* b = dynamic_cast<const dds_bridge::DdsBridge*>(c.get());
        b != nullptr && b->robot_id() == 2)
      for (const auto& t : b->stats().topics)
        r2.push_back((t.exported ? "out " : "in ") + t.local + " " + t.dds_topic);
  EXPECT_EQ(r2, (std::vector<std::string>{
                    "out /r2/robot_state sc/r2/robot_state", "in /r1/robot_state sc/r1/robot_state",
                    "in /r3/robot_state sc/r3/robot_state", "in /r1/mission sc/r1/mission",
                    "in /r2/mission sc/r2/mission", "in /r3/mission sc/r3/mission"}));
}

TEST(DdsBridge, BadPlaceholdersAndLoopsFailAtStart) {
  EXPECT_NE(launch_errors("import_topics: ['/x{team}/plan']").find("is not a topic name"),
            std::string::npos);
  EXPECT_NE(launch_errors("export_topics: [/a/plan], import_topics: [/a/plan], "
                          "type_a_plan: scancrew/TeamPlan")
                .find("is exported too"),
            std::string::npos);
  EXPECT_NE(launch_errors("import_topics: [plan], type_plan: scancrew/TeamPlan, "
                          "link_loss_topics: [other]")
                .find("'other' is not an imported topic"),
            std::string::npos);
  // {self} needs a per-robot bridge; a leader must carry the simulator's id
  EXPECT_NE(launch_errors("import_topics: ['/{self}/plan'], type_self_plan: scancrew/TeamPlan")
                .find("needs the launch file's robots"),
            std::string::npos);
  EXPECT_NE(launch_errors("import_topics: [plan], type_plan: scancrew/TeamPlan, lockstep: leader")
                .find("must be simulator_id"),
            std::string::npos);
}

}  // namespace
}  // namespace scancrew::dds_bridge
