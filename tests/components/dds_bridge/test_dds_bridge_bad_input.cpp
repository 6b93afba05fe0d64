// The dds_bridge over real Fast DDS on bad input (bridge_harness.hpp): malformed envelopes
// written by a raw DDS writer are rejected and counted while good samples flow; an envelope
// from a participant that did not announce its robot is refused; a second participant of a
// robot takes over when the first leaves.
//
// Waits are polls with generous bounds (a loaded 2-core machine), never fixed sleeps.

#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "components/dds_bridge/dds_bridge.hpp"
#include "interfaces/codec.hpp"
#include "tests/components/dds_bridge/bridge_harness.hpp"

namespace scancrew::dds_bridge {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

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

}  // namespace
}  // namespace scancrew::dds_bridge
