// The dds_bridge component over real Fast DDS: several launches in one process (separate
// participants) on UDPv4 loopback, in a domain and a DDS partition drawn from the process id
// so parallel test processes do not hear each other. Robot state, team plans and patches
// cross; the link model drops a deterministic share and partitions a pair; malformed
// envelopes written by a raw DDS writer are rejected and counted while good samples flow;
// a destroyed launch, and a killed process, are reported lost.
//
// Waits are polls with generous bounds (a loaded 2-core machine), never fixed sleeps.

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include "components/dds_bridge/dds_bridge.hpp"
#include "components/dds_bridge/idl/envelopePubSubTypes.h"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "interfaces/codec.hpp"
#include "tests/components/dds_bridge/bridge_harness.hpp"

namespace scancrew::dds_bridge {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

TEST(DdsBridge, RobotStatePlansAndPatchesReachTeammatesAndTheStation) {
  Robot r1(1, ""), r2(2, ""), station(0, "");
  wait_ready({&r1, &r2, &station}, 3);

  constexpr int kStates = 20;
  for (int i = 1; i <= kStates; ++i) {
    ASSERT_TRUE(r1.source().send_state(static_cast<uint32_t>(i)));
    ASSERT_TRUE(r2.source().send_state(static_cast<uint32_t>(100 + i)));
  }
  ASSERT_TRUE(r1.source().send_plan(42));
  ASSERT_TRUE(r1.source().send_patch(1, 1000));
  ASSERT_TRUE(r1.source().send_patch(2, 300'000));  // fragmented by DDS

  ASSERT_TRUE(wait_until([&] {
    std::lock_guard lock(r2.sink().mutex);
    return r2.sink().states.size() == kStates && r2.sink().plans.size() == 1 &&
           r2.sink().patches.size() == 2;
  })) << "robot 2 got "
      << r2.sink().count(r2.sink().states) << " states";
  ASSERT_TRUE(wait_until([&] {
    return station.sink().count(station.sink().states) == 2 * size_t{kStates};
  })) << describe(station)
      << "\n"
      << describe(r1) << "\n"
      << describe(r2);

  // robot 2 sees robot 1's messages whole: its robot id, sequence numbers and contents
  const auto states = r2.sink().copy(r2.sink().states);
  for (size_t i = 0; i < states.size(); ++i) {
    EXPECT_EQ(states[i].header.robot_id, 1u);
    EXPECT_EQ(states[i].header.seq, i + 1);
    EXPECT_EQ(states[i].path_index, i + 1);
    EXPECT_EQ(states[i].mode, msg::RobotState::Mode::kMoving);
    EXPECT_DOUBLE_EQ(states[i].T_world_body.position.x, 0.5 * static_cast<double>(i + 1));
  }
  const auto plans = r2.sink().copy(r2.sink().plans);
  EXPECT_EQ(plans[0].plan_id, 42u);
  ASSERT_EQ(plans[0].sequences.size(), 1u);
  EXPECT_EQ(plans[0].sequences[0].cluster_ids, (std::vector<uint32_t>{3, 1, 4}));
  EXPECT_EQ(plans[0].sequences[0].viewpoints.size(), 2u);
  const auto patches = r2.sink().copy(r2.sink().patches);
  EXPECT_EQ(patches[1].patch_id, (uint64_t{1} << 32) | 2);
  ASSERT_EQ(patches[1].data.size(), 300'000u);
  for (size_t i = 0; i < patches[1].data.size(); i += 997)
    ASSERT_EQ(patches[1].data[i], static_cast<uint8_t>(i * 31 + 2)) << i;

  // the station hears both robots; nobody re-imports its own samples
  std::map<uint32_t, int> by_robot;
  for (const auto& s : station.sink().copy(station.sink().states)) ++by_robot[s.header.robot_id];
  EXPECT_EQ(by_robot[1], kStates);
  EXPECT_EQ(by_robot[2], kStates);
  for (const auto& s : r1.sink().copy(r1.sink().states)) EXPECT_EQ(s.header.robot_id, 2u);
  ASSERT_TRUE(wait_until(
      [&] { return counters(r1.bridge().stats(), "robot_state", false).own_ignored == kStates; }));

  // byte counters: what robot 1 sent is what robot 2 received from it
  const BridgeStats s1 = r1.bridge().stats();
  const BridgeStats s2 = r2.bridge().stats();
  const TopicCounters& sent = counters(s1, "patch", true);
  const TopicCounters& got = counters(s2, "patch", false);
  EXPECT_EQ(sent.sent_samples, 2u);
  EXPECT_GT(sent.sent_bytes, 301'000u);
  EXPECT_EQ(got.received_samples, 2u);
  EXPECT_EQ(got.received_bytes, sent.sent_bytes);
  EXPECT_EQ(got.delivered, 2u);
  EXPECT_EQ(got.rejected_total(), 0u);
  EXPECT_EQ(counters(s2, "robot_state", false).received_bytes,
            counters(s1, "robot_state", true).sent_bytes);
  EXPECT_EQ(counters(s1, "robot_state", true).sent_samples, static_cast<uint64_t>(kStates));
  EXPECT_GT(s1.sent_bytes(), 0u);
  EXPECT_EQ(counters(s2, "robot_state", false).local, "/r2/remote/robot_state");
  EXPECT_EQ(counters(s2, "robot_state", false).dds_topic, "sc/robot_state");
}

TEST(DdsBridge, LinkLossDropsTheConfiguredShareDeterministically) {
  constexpr double kLoss = 0.2;
  constexpr uint64_t kSeed = 7;
  Robot r1(1, "", "[robot_state]");
  Robot r2(2, ", link_loss_rate: 0.2, link_seed: 7", "[robot_state]");
  wait_ready({&r1, &r2}, 2, {"robot_state"});

  constexpr int kStates = 300;
  for (int i = 1; i <= kStates; ++i) ASSERT_TRUE(r1.source().send_state(static_cast<uint32_t>(i)));
  ASSERT_TRUE(wait_until([&] {
    const TopicCounters c = counters(r2.bridge().stats(), "robot_state", false);
    return c.received_samples == kStates && c.delivered + c.dropped_loss == kStates;
  })) << describe(r2)
      << "\n"
      << describe(r1);
  ASSERT_TRUE(wait_until([&] {
    return r2.sink().count(r2.sink().states) ==
           counters(r2.bridge().stats(), "robot_state", false).delivered;
  }));

  const TopicCounters c = counters(r2.bridge().stats(), "robot_state", false);
  const double dropped = static_cast<double>(c.dropped_loss) / kStates;
  EXPECT_NEAR(dropped, kLoss, 0.06) << c.dropped_loss << " of " << kStates;
  // exactly the samples the seeded draw marks lost are missing (the same on every run)
  std::set<uint64_t> expected, got;
  const uint64_t key = LinkModel::topic_key("sc/robot_state");
  for (uint64_t seq = 1; seq <= kStates; ++seq)
    if (LinkModel::loss_draw(kSeed, 1, 2, key, seq) >= kLoss) expected.insert(seq);
  for (const auto& s : r2.sink().copy(r2.sink().states)) got.insert(s.header.seq);
  EXPECT_EQ(got, expected);
  // robot 1 has no link model: it loses nothing of robot 2's (none sent) and counts nothing
  EXPECT_EQ(counters(r1.bridge().stats(), "robot_state", false).link_dropped(), 0u);
}

TEST(DdsBridge, APartitionCutsTheLinkBetweenTwoRobots) {
  // Fig. 4.2 connected graph: 1 hears 2 and 3; 2 and 3 do not hear each other
  const std::string partition = R"(, link_partition: ["1 2", "1 3"])";
  Robot r1(1, partition, "[robot_state]"), r2(2, partition, "[robot_state]"),
      r3(3, partition, "[robot_state]");
  wait_ready({&r1, &r2, &r3}, 3, {"robot_state"});

  constexpr int kStates = 5;
  for (int i = 1; i <= kStates; ++i)
    for (Robot* r : {&r1, &r2, &r3}) ASSERT_TRUE(r->source().send_state(static_cast<uint32_t>(i)));
  for (Robot* r : {&r1, &r2, &r3})
    ASSERT_TRUE(wait_until([&] {
      return counters(r->bridge().stats(), "robot_state", false).received_samples ==
             2 * size_t{kStates};
    }));
  ASSERT_TRUE(wait_until([&] { return r1.sink().count(r1.sink().states) == 2 * size_t{kStates}; }));
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().states) == kStates; }));
  ASSERT_TRUE(wait_until([&] { return r3.sink().count(r3.sink().states) == kStates; }));

  for (const auto& s : r2.sink().copy(r2.sink().states)) EXPECT_EQ(s.header.robot_id, 1u);
  for (const auto& s : r3.sink().copy(r3.sink().states)) EXPECT_EQ(s.header.robot_id, 1u);
  EXPECT_EQ(counters(r2.bridge().stats(), "robot_state", false).dropped_partition,
            static_cast<uint64_t>(kStates));
  EXPECT_EQ(counters(r3.bridge().stats(), "robot_state", false).dropped_partition,
            static_cast<uint64_t>(kStates));
  EXPECT_EQ(counters(r1.bridge().stats(), "robot_state", false).dropped_partition, 0u);
}

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

TEST(DdsBridge, BadEnvelopesAreRejectedAndCountedWhileGoodSamplesFlow) {
  Robot r1(1, ", max_sample_bytes: 4096", "[robot_state]");
  Robot r2(2, ", max_sample_bytes: 4096", "[robot_state]");
  wait_ready({&r1, &r2}, 2, {"robot_state"});
  RawPeer raw;
  ASSERT_TRUE(wait_until([&] { return raw.matched() >= 2; }));
  for (Robot* r : {&r1, &r2})  // and the bridges' readers know the raw writer
    ASSERT_TRUE(wait_until([&] { return r->bridge().matched("robot_state", false) >= 3; }));

  const uint32_t v = msg::kMessageFormatVersion;
  const std::string type = msg::RobotState::kTypeName;
  std::vector<uint8_t> truncated = state_bytes(3, 1);
  truncated.resize(truncated.size() / 2);
  std::vector<uint8_t> trailing = state_bytes(3, 1);
  trailing.push_back(0);
  std::vector<uint8_t> plan_with_huge_count = msg::encode(msg::TeamPlan{});
  plan_with_huge_count[plan_with_huge_count.size() - 8] = 0xff;  // sequences: 0xff... entries
  plan_with_huge_count[plan_with_huge_count.size() - 5] = 0x7f;

  uint64_t seq = 0;
  int good = 0;
  const auto good_one = [&] {
    ++seq;
    ASSERT_TRUE(raw.write(v, 3, seq, type, state_bytes(3, static_cast<uint32_t>(seq))));
    ASSERT_TRUE(r1.source().send_state(static_cast<uint32_t>(++good)));
  };
  good_one();
  ASSERT_TRUE(raw.write(v + 1, 3, ++seq, type, state_bytes(3, 1)));  // another format
  good_one();
  ASSERT_TRUE(raw.write(v, 3, ++seq, "scancrew/Nope", state_bytes(3, 1)));  // unknown type
  ASSERT_TRUE(raw.write(v, 3, ++seq, msg::TeamPlan::kTypeName, plan_with_huge_count));  // mismatch
  good_one();
  ASSERT_TRUE(raw.write(v, 3, ++seq, type, std::vector<uint8_t>(5000, 0xab)));  // oversized
  ASSERT_TRUE(raw.write(v, 9, ++seq, type, state_bytes(9, 1)));   // robot 9 is not in the team
  ASSERT_TRUE(raw.write(v, 3, ++seq, type, state_bytes(99, 1)));  // header names robot 99
  good_one();
  ASSERT_TRUE(raw.write(v, 3, ++seq, type, truncated));
  ASSERT_TRUE(raw.write(v, 3, ++seq, type, trailing));
  ASSERT_TRUE(raw.write(v, 3, ++seq, type, {}));
  good_one();

  // robot 2: 5 good from robot 1, 5 good from the raw peer (as robot 3), 9 rejected
  const auto done = [&] {
    const TopicCounters c = counters(r2.bridge().stats(), "robot_state", false);
    return c.delivered == 10 && c.rejected_total() == 9;
  };
  ASSERT_TRUE(wait_until(done)) << "delivered "
                                << counters(r2.bridge().stats(), "robot_state", false).delivered;
  const TopicCounters c = counters(r2.bridge().stats(), "robot_state", false);
  EXPECT_EQ(c.rejected[static_cast<size_t>(Reject::kFormatVersion)], 1u);
  EXPECT_EQ(c.rejected[static_cast<size_t>(Reject::kUnknownType)], 1u);
  EXPECT_EQ(c.rejected[static_cast<size_t>(Reject::kTypeMismatch)], 1u);
  EXPECT_EQ(c.rejected[static_cast<size_t>(Reject::kOversize)], 1u);
  EXPECT_EQ(c.rejected[static_cast<size_t>(Reject::kUnknownRobot)], 2u);
  EXPECT_EQ(c.rejected[static_cast<size_t>(Reject::kMalformed)], 3u);
  EXPECT_EQ(c.received_samples, 19u);

  // only the good samples reached the graph, intact and in order per sender
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().states) == 10; }));
  std::map<uint32_t, std::vector<uint32_t>> by_robot;
  for (const auto& s : r2.sink().copy(r2.sink().states))
    by_robot[s.header.robot_id].push_back(s.path_index);
  EXPECT_EQ(by_robot[1], (std::vector<uint32_t>{1, 2, 3, 4, 5}));
  EXPECT_EQ(by_robot[3], (std::vector<uint32_t>{1, 3, 6, 10, 14}));
  EXPECT_EQ(by_robot.size(), 2u);
  // robot 1 saw the same bad input and keeps running: it still exports
  ASSERT_TRUE(r1.source().send_state(99));
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().states) == 11; }));
  EXPECT_EQ(counters(r1.bridge().stats(), "robot_state", false).rejected_total(), 9u);
}

// Nothing tied an envelope's robot id to its sender: any participant could send as any robot.
// A participant that announced robot 3 sends as robot 1, and one that announces robot 1 while
// robot 1's bridge is in the domain, and one that announces nothing: all refused, counted as
// forged; robot 3's own samples flow.
TEST(DdsBridge, AnEnvelopeFromAParticipantThatDidNotAnnounceItsRobotIsRefused) {
  Robot r1(1, "", "[robot_state]");
  Robot r2(2, "", "[robot_state]");
  wait_ready({&r1, &r2}, 2, {"robot_state"});
  RawPeer as3(3), second1(1), anonymous(std::nullopt);
  for (RawPeer* p : {&as3, &second1, &anonymous})
    ASSERT_TRUE(wait_until([&] { return p->matched() >= 2; }));
  ASSERT_TRUE(wait_until([&] { return r2.bridge().matched("robot_state", false) >= 4; }));

  const uint32_t v = msg::kMessageFormatVersion;
  const std::string type = msg::RobotState::kTypeName;
  ASSERT_TRUE(as3.write(v, 1, 1000, type, state_bytes(1, 1000)));        // robot 3 as robot 1
  ASSERT_TRUE(second1.write(v, 1, 1001, type, state_bytes(1, 1001)));    // a second robot 1
  ASSERT_TRUE(anonymous.write(v, 1, 1002, type, state_bytes(1, 1002)));  // no announcement
  ASSERT_TRUE(as3.write(v, 3, 1, type, state_bytes(3, 7)));              // robot 3 as itself
  ASSERT_TRUE(r1.source().send_state(1));                                // robot 1's own

  const auto done = [&] {
    const TopicCounters c = counters(r2.bridge().stats(), "robot_state", false);
    return c.delivered == 2 && c.rejected_total() == 3;
  };
  ASSERT_TRUE(wait_until(done)) << "delivered "
                                << counters(r2.bridge().stats(), "robot_state", false).delivered;
  const TopicCounters c = counters(r2.bridge().stats(), "robot_state", false);
  EXPECT_EQ(c.rejected[static_cast<size_t>(Reject::kForgedSender)], 3u);
  // robot 1's real samples still flow after the forgeries (its sequence was not advanced)
  ASSERT_TRUE(r1.source().send_state(2));
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().states) == 3; }));
  std::map<uint32_t, std::vector<uint32_t>> by_robot;
  for (const auto& st : r2.sink().copy(r2.sink().states))
    by_robot[st.header.robot_id].push_back(st.path_index);
  EXPECT_EQ(by_robot[1], (std::vector<uint32_t>{1, 2}));
  EXPECT_EQ(by_robot[3], (std::vector<uint32_t>{7}));
}

// A robot that restarts announces its id while its old participant may still be in the domain
// (a crash sends no goodbye): refused until the old one leaves, then it holds the id.
TEST(DdsBridge, ASecondParticipantOfARobotTakesOverWhenTheFirstLeaves) {
  auto r1 = std::make_unique<Robot>(1, "", "[robot_state]");
  Robot r2(2, "", "[robot_state]");
  wait_ready({r1.get(), &r2}, 2, {"robot_state"});
  RawPeer restarted(1);
  ASSERT_TRUE(wait_until([&] { return restarted.matched() >= 2; }));
  ASSERT_TRUE(wait_until([&] { return r2.bridge().matched("robot_state", false) >= 2; }));
  const uint32_t v = msg::kMessageFormatVersion;
  const std::string type = msg::RobotState::kTypeName;
  ASSERT_TRUE(restarted.write(v, 1, 1, type, state_bytes(1, 500)));
  ASSERT_TRUE(wait_until([&] {
    return counters(r2.bridge().stats(), "robot_state", false)
               .rejected[static_cast<size_t>(Reject::kForgedSender)] == 1;
  }));
  r1.reset();  // the first participant leaves the domain
  ASSERT_TRUE(wait_until([&] {
    (void)restarted.write(v, 1, 2, type, state_bytes(1, 501));
    return r2.sink().count(r2.sink().states) >= 1;
  }));
  for (const auto& st : r2.sink().copy(r2.sink().states)) EXPECT_EQ(st.header.robot_id, 1u);
}

TEST(DdsBridge, ADestroyedTeammateIsReportedLost) {
  auto r1 = std::make_unique<Robot>(1, "", "[robot_state]");
  Robot r2(2, "", "[robot_state]");
  wait_ready({r1.get(), &r2}, 2, {"robot_state"});
  ASSERT_TRUE(wait_until([&] { return r2.bridge().peers_alive() == 1; }));
  EXPECT_EQ(r2.sink().count(r2.sink().lost), 0u);

  const auto t0 = Clock::now();
  r1->destroy();
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().lost) >= 1; }, 10.0));
  const double took_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto lost = r2.sink().copy(r2.sink().lost);
  EXPECT_EQ(lost[0].header.robot_id, 1u);
  EXPECT_EQ(lost[0].mode, msg::RobotState::Mode::kLost);
  EXPECT_EQ(r2.bridge().stats().peers_lost, 1u);
  EXPECT_EQ(r2.bridge().peers_alive(), 0u);
  std::printf("robot 1 reported lost %.3f s after its launch was destroyed\n", took_s);
}

// The child of the next test: a robot that runs until it is killed.
TEST(DdsBridgeChild, RunsARobotUntilKilled) {
  // NOLINTNEXTLINE(concurrency-mt-unsafe): getenv is read before any thread starts
  if (std::getenv("SCANCREW_DDS_TEST_CHILD") == nullptr)
    GTEST_SKIP() << "only run as the child process of AKilledRobotProcessIsReportedLost...";
  Robot r4(4, "", "[robot_state]");
  ASSERT_TRUE(wait_until([&] { return r4.active(); }));
  std::this_thread::sleep_for(std::chrono::seconds(60));  // the parent kills us long before
}

// Kills the child process on every exit path of the test.
struct ChildGuard {
  pid_t pid = -1;
  ~ChildGuard() { kill_now(); }
  void kill_now() {
    if (pid <= 0) return;
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    pid = -1;
  }
};

// Starts this binary's child test (robot 4) in our domain and partition.
void spawn_child_robot(ChildGuard& child) {
  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e)
    if (std::string_view(*e).substr(0, 24) != "SCANCREW_DDS_TEST_CHILD=")
      env_strings.emplace_back(*e);
  env_strings.push_back("SCANCREW_DDS_TEST_CHILD=" + std::to_string(::getpid()));
  std::vector<char*> envp;
  envp.reserve(env_strings.size() + 1);
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::string exe = "/proc/self/exe";
  std::string filter = "--gtest_filter=DdsBridgeChild.RunsARobotUntilKilled";
  std::vector<char*> argv = {exe.data(), filter.data(), nullptr};
  ASSERT_EQ(::posix_spawn(&child.pid, exe.c_str(), nullptr, nullptr, argv.data(), envp.data()), 0);
}

// Robot 3 stays alive beside it: Fast DDS 2.9's liveliness, asserted by any live writer for
// every one it tracks, never reported the killed robot lost with a live teammate in the
// domain (only the 20 s participant lease did; the bridge now sets that lease to its own).
TEST(DdsBridge, AKilledRobotProcessIsReportedLostWhenItsLeaseRunsOut) {
  Robot r2(2, "", "[robot_state]");
  Robot r3(3, "", "[robot_state]");
  ASSERT_TRUE(r2.ok());
  ASSERT_TRUE(wait_until([&] { return r2.active(); }));
  ChildGuard child;
  spawn_child_robot(child);
  ASSERT_TRUE(wait_until([&] { return r2.bridge().peers_alive() == 2; }, 30.0))
      << "the child robot never appeared";
  ASSERT_EQ(r2.sink().count(r2.sink().lost), 0u);
  const auto t0 = Clock::now();
  child.kill_now();  // no goodbye: only the liveliness lease can tell
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().lost) >= 1; }, 10.0));
  const double took_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto lost = r2.sink().copy(r2.sink().lost);
  EXPECT_EQ(lost[0].header.robot_id, 4u);
  EXPECT_EQ(lost[0].mode, msg::RobotState::Mode::kLost);
  EXPECT_LT(took_s, 5.0) << "a 1 s participant lease (Fast DDS's default is 20 s)";
  std::printf("killed robot 4 reported lost %.3f s after SIGKILL (participant lease 1 s)\n",
              took_s);
}

// A restarted robot: its old process was killed (no goodbye) and the new one starts at once,
// while the old participant is still in the domain: refused until the old one leaves (its
// participant lease, 1 s at least), it then holds the robot's id and its samples count.
TEST(DdsBridge, ARestartedRobotProcessTakesOverItsIdOnceTheOldOneIsLost) {
  Robot r2(2, "", "[robot_state]");
  ASSERT_TRUE(r2.ok());
  ASSERT_TRUE(wait_until([&] { return r2.active(); }));
  ChildGuard child;
  spawn_child_robot(child);
  ASSERT_TRUE(wait_until([&] { return r2.bridge().peers_alive() == 1; }, 30.0))
      << "the child robot never appeared";
  child.kill_now();
  const auto t0 = Clock::now();
  Robot r4(4, "", "[robot_state]");  // the restarted process
  ASSERT_TRUE(wait_until(
      [&] { return r2.sink().count(r2.sink().lost) >= 1 && r2.bridge().peers_alive() == 1; }, 15.0))
      << "the old robot 4 was not reported lost, or the restarted one not taken for robot 4";
  const double took_s = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_LT(took_s, 5.0) << "a 1 s participant lease (Fast DDS's default is 20 s)";
  const auto heard = [&] {
    for (const msg::RobotState& s : r2.sink().copy(r2.sink().states))
      if (s.header.robot_id == 4 && s.path_index == 7) return true;
    return false;
  };
  ASSERT_TRUE(wait_until([&] {
    if (heard()) return true;
    (void)r4.source().send_state(7);
    return false;
  })) << "the restarted robot's samples are refused";
  EXPECT_EQ(r2.bridge().stats().peers_lost, 1u);
  std::printf("restarted robot 4 taken over %.3f s after it started\n", took_s);
}

}  // namespace
}  // namespace scancrew::dds_bridge
