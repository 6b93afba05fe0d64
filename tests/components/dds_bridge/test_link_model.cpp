// The bridge's link model (components/dds_bridge/link_model.hpp): partitions as
// communication graphs (thesis Fig. 4.2), deterministic loss, latency and a bandwidth cap,
// and the envelope checks that guard the decoder.

#include <gtest/gtest.h>

#include "components/dds_bridge/envelope_check.hpp"
#include "components/dds_bridge/link_model.hpp"
#include "interfaces/codec.hpp"

namespace scancrew::dds_bridge {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(PartitionGroup, ParsesIdsSeparatedBySpacesOrCommas) {
  std::vector<uint32_t> group;
  EXPECT_EQ(parse_partition_group("1 2 3", group), "");
  EXPECT_EQ(group, (std::vector<uint32_t>{1, 2, 3}));
  EXPECT_EQ(parse_partition_group("0,7", group), "");
  EXPECT_EQ(group, (std::vector<uint32_t>{0, 7}));
  EXPECT_NE(parse_partition_group("1 x", group), "");
  EXPECT_NE(parse_partition_group("1-2", group), "");
  EXPECT_NE(parse_partition_group("", group), "");
  EXPECT_NE(parse_partition_group("99999999999", group), "");
}

TEST(LinkModel, ACompleteGraphHearsEveryone) {
  LinkModel model({}, 2);
  for (uint32_t sender : {0u, 1u, 3u, 1000u}) EXPECT_TRUE(model.hears(sender));
  const auto d = model.admit(1, 7, 1, 100, 5 * kMs);
  EXPECT_EQ(d.verdict, LinkVerdict::kDeliver);
  EXPECT_EQ(d.deliver_at_ns, 5 * kMs);
}

TEST(LinkModel, PartitionGroupsMakeAConnectedButIncompleteGraph) {
  // Fig. 4.2 middle-left: 1 talks to 2 and 3, 2 and 3 do not hear each other; 4 is alone
  LinkConfig c;
  c.partition = {{1, 2}, {1, 3}};
  EXPECT_TRUE(LinkModel(c, 1).hears(2));
  EXPECT_TRUE(LinkModel(c, 1).hears(3));
  EXPECT_TRUE(LinkModel(c, 2).hears(1));
  EXPECT_FALSE(LinkModel(c, 2).hears(3));
  EXPECT_FALSE(LinkModel(c, 3).hears(2));
  EXPECT_FALSE(LinkModel(c, 4).hears(1));
  EXPECT_FALSE(LinkModel(c, 1).hears(4));
  LinkModel two(c, 2);
  EXPECT_EQ(two.admit(3, 7, 1, 100, 0).verdict, LinkVerdict::kPartitioned);
}

TEST(LinkModel, LossIsDeterministicAndNearItsRate) {
  LinkConfig c;
  c.loss_rate = 0.2;
  c.seed = 42;
  const uint64_t topic = LinkModel::topic_key("sc/robot_state");
  LinkModel a(c, 2), b(c, 2);
  int lost = 0;
  const int n = 20000;
  for (int seq = 1; seq <= n; ++seq) {
    const auto va = a.admit(1, topic, static_cast<uint64_t>(seq), 100, 0).verdict;
    const auto vb = b.admit(1, topic, static_cast<uint64_t>(seq), 100, 0).verdict;
    ASSERT_EQ(va, vb) << "seq " << seq;
    lost += va == LinkVerdict::kLost;
  }
  EXPECT_NEAR(static_cast<double>(lost) / n, 0.2, 0.01);

  // another seed, another pattern; another receiver, another pattern
  c.seed = 43;
  LinkModel other_seed(c, 2);
  c.seed = 42;
  LinkModel other_receiver(c, 3);
  int differ_seed = 0, differ_receiver = 0;
  LinkModel again(c, 2);
  for (int seq = 1; seq <= 1000; ++seq) {
    const auto ref = again.admit(1, topic, static_cast<uint64_t>(seq), 100, 0).verdict;
    differ_seed += other_seed.admit(1, topic, static_cast<uint64_t>(seq), 100, 0).verdict != ref;
    differ_receiver +=
        other_receiver.admit(1, topic, static_cast<uint64_t>(seq), 100, 0).verdict != ref;
  }
  EXPECT_GT(differ_seed, 100);
  EXPECT_GT(differ_receiver, 100);
}

TEST(LinkModel, LossRatesZeroAndOneAreExact) {
  LinkConfig c;
  c.loss_rate = 1.0;
  LinkModel all(c, 1);
  c.loss_rate = 0.0;
  LinkModel none(c, 1);
  for (uint64_t seq = 1; seq <= 1000; ++seq) {
    EXPECT_EQ(all.admit(2, 5, seq, 10, 0).verdict, LinkVerdict::kLost);
    EXPECT_EQ(none.admit(2, 5, seq, 10, 0).verdict, LinkVerdict::kDeliver);
  }
}

TEST(LinkModel, LatencyDelaysEverySample) {
  LinkConfig c;
  c.latency_s = 0.25;
  LinkModel model(c, 1);
  EXPECT_EQ(model.admit(2, 5, 1, 10, 1000 * kMs).deliver_at_ns, 1250 * kMs);
  EXPECT_EQ(model.admit(2, 5, 2, 10, 1001 * kMs).deliver_at_ns, 1251 * kMs);
}

TEST(LinkModel, BandwidthSerialisesSamplesAndASaturatedChannelDrops) {
  LinkConfig c;
  c.bandwidth_bps = 80'000;  // 1000 bytes take 100 ms
  c.max_queue_s = 0.35;
  LinkModel model(c, 1);
  // five samples arrive at once: 0.1, 0.2, 0.3, 0.4 s; the fifth would wait 0.4 s > 0.35 s
  for (int64_t i = 1; i <= 4; ++i) {
    const auto d = model.admit(2, 5, static_cast<uint64_t>(i), 1000, 0);
    ASSERT_EQ(d.verdict, LinkVerdict::kDeliver);
    EXPECT_EQ(d.deliver_at_ns, i * 100 * kMs);
  }
  EXPECT_EQ(model.admit(3, 5, 1, 1000, 0).verdict, LinkVerdict::kSaturated);
  // once the channel is free again, samples pass at line rate
  const auto later = model.admit(2, 5, 6, 500, 2000 * kMs);
  EXPECT_EQ(later.verdict, LinkVerdict::kDeliver);
  EXPECT_EQ(later.deliver_at_ns, 2050 * kMs);
}

WireEnvelope good_state() {
  msg::RobotState state;
  state.header.robot_id = 1;
  WireEnvelope e;
  e.format_version = msg::kMessageFormatVersion;
  e.robot_id = 1;
  e.sender_robot_id = 1;  // its participant announced robot 1 at discovery
  e.seq = 1;
  e.type_name = msg::RobotState::kTypeName;
  e.payload = msg::encode(state);
  return e;
}

TEST(EnvelopeCheck, AcceptsAGoodEnvelopeAndNamesEachRejection) {
  EnvelopeRules rules{msg::kMessageFormatVersion, {0, 1, 2}, 1024};
  const std::string type = msg::RobotState::kTypeName;
  std::string detail;
  EXPECT_EQ(check_envelope(good_state(), type, rules, &detail), std::nullopt);

  WireEnvelope e = good_state();
  e.format_version = msg::kMessageFormatVersion + 1;
  EXPECT_EQ(check_envelope(e, type, rules, &detail), Reject::kFormatVersion);
  EXPECT_NE(detail.find("message format"), std::string::npos) << detail;

  e = good_state();
  e.robot_id = 9;
  EXPECT_EQ(check_envelope(e, type, rules, &detail), Reject::kUnknownRobot);

  // a participant that announced robot 2 (or none) sends as robot 1
  e = good_state();
  e.sender_robot_id = 2;
  EXPECT_EQ(check_envelope(e, type, rules, &detail), Reject::kForgedSender);
  EXPECT_NE(detail.find("announced robot 2"), std::string::npos) << detail;
  e.sender_robot_id = kUnknownSender;
  EXPECT_EQ(check_envelope(e, type, rules, &detail), Reject::kForgedSender);

  e = good_state();
  e.type_name = "scancrew/NoSuchThing" + std::string(1000, 'x');
  EXPECT_EQ(check_envelope(e, type, rules, &detail), Reject::kUnknownType);
  EXPECT_LT(detail.size(), 200u) << "a hostile type name is not echoed whole";

  e = good_state();
  e.type_name = msg::TeamPlan::kTypeName;
  EXPECT_EQ(check_envelope(e, type, rules, &detail), Reject::kTypeMismatch);

  e = good_state();
  e.payload.resize(1025);
  EXPECT_EQ(check_envelope(e, type, rules, &detail), Reject::kOversize);

  rules.team.clear();  // anyone
  e = good_state();
  e.robot_id = 77;
  e.sender_robot_id = 77;
  EXPECT_EQ(check_envelope(e, type, rules, &detail), std::nullopt);
}

TEST(EnvelopeCheck, ParticipantUserDataNamesOnlyABridgesRobotOfThesePartitions) {
  const std::vector<std::string> none, team = {"b", "a"};
  EXPECT_EQ(robot_of_user_data(participant_user_data(7, none), none), 7u);
  EXPECT_EQ(robot_of_user_data(participant_user_data(0, none), none), 0u);
  EXPECT_EQ(robot_of_user_data(participant_user_data(7, team), {"a", "b"}), 7u);  // any order
  // another team sharing the domain (other partitions) claims nothing here
  EXPECT_EQ(robot_of_user_data(participant_user_data(7, team), none), std::nullopt);
  EXPECT_EQ(robot_of_user_data(participant_user_data(7, none), team), std::nullopt);
  EXPECT_EQ(robot_of_user_data(participant_user_data(7, {"a"}), team), std::nullopt);
  const auto text = [](const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); };
  EXPECT_EQ(robot_of_user_data({}, none), std::nullopt);
  EXPECT_EQ(robot_of_user_data(text("scancrew robot "), none), std::nullopt);
  EXPECT_EQ(robot_of_user_data(text("scancrew robot 1x"), none), std::nullopt);
  EXPECT_EQ(robot_of_user_data(text("scancrew robot 4294967295"), none), std::nullopt);
  EXPECT_EQ(robot_of_user_data(text("scancrew robot 99999999999"), none), std::nullopt);
  EXPECT_EQ(robot_of_user_data(text("another application"), none), std::nullopt);
}

}  // namespace
}  // namespace scancrew::dds_bridge
