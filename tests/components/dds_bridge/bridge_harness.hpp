#pragma once

// The dds_bridge tests' harness: launches of one robot (or station) each, with a source
// and a sink component around a bridge, in a domain and a DDS partition drawn from the
// process id so parallel test processes do not hear each other; a bare Fast DDS participant
// writing raw envelopes (the hostile peer). The test components are registered in
// bridge_harness.cpp, linked once into each test executable that includes this header.
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

namespace scancrew::dds_bridge::testing {

namespace fdds = eprosima::fastdds::dds;
using Clock = std::chrono::steady_clock;

// Polls pred every 5 ms for up to timeout_s.
inline bool wait_until(const std::function<bool()>& pred, double timeout_s = 15.0) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < deadline) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return pred();
}

// Publishes what the test asks for, from the test thread (publishers are thread safe).
class Source final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: publishes on the test's demand";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  Source(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  bool active() const { return active_.load(); }
  // Each waits for a free slot (the bridge may hold some), up to a bound.
  bool send_state(uint32_t path_index) {
    return send(state_, [&](msg::RobotState& m) {
      m.mode = msg::RobotState::Mode::kMoving;
      m.path_index = path_index;
      m.T_world_body.position = {0.5 * path_index, -1.0, 0.25};
    });
  }
  bool send_plan(uint64_t plan_id) {
    return send(plan_, [&](msg::TeamPlan& m) {
      m.plan_id = plan_id;
      m.map_version = 7;
      msg::PathSequence seq;
      seq.robot_id = robot_id();
      seq.cluster_ids = {3, 1, 4};
      seq.viewpoints = {{{1, 2, 0}, 0.5}, {{2, 3, 0}, 1.0}};
      seq.utility = 0.75;
      m.sequences = {seq};
    });
  }
  bool send_patch(uint32_t index, size_t bytes) {
    return send(patch_, [&](msg::TsdfPatch& m) {
      m.robot_id = robot_id();
      m.index = index;
      m.patch_id = (uint64_t{robot_id()} << 32) | index;
      m.voxel_size_m = 0.05;
      m.data.resize(bytes);
      for (size_t i = 0; i < bytes; ++i) m.data[i] = static_cast<uint8_t>(i * 31 + index);
    });
  }

 private:
  template <class T, class Fill>
  bool send(Publisher<T>& pub, Fill&& fill) {
    bool sent = false;
    wait_until([&] {
      auto loan = pub.loan();
      if (!loan) return false;
      fill(**loan);
      sent = pub.publish(std::move(*loan)).has_value();
      return true;
    });
    return sent;
  }
  Result<void, std::string> on_configure() override {
    state_ = create_publisher<msg::RobotState>("robot_state");
    plan_ = create_publisher<msg::TeamPlan>("plan");
    patch_ = create_publisher<msg::TsdfPatch>("patch");
    return {};
  }
  void on_activate() override { active_.store(true); }
  void on_deactivate() override { active_.store(false); }

  Publisher<msg::RobotState> state_;
  Publisher<msg::TeamPlan> plan_;
  Publisher<msg::TsdfPatch> patch_;
  std::atomic<bool> active_{false};
};

// Keeps what the bridge imports and the loss reports.
class Sink final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps what the bridge imports";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  Sink(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  mutable std::mutex mutex;
  std::vector<msg::RobotState> states, lost;
  std::vector<msg::TeamPlan> plans;
  std::vector<msg::TsdfPatch> patches;

  size_t count(const std::vector<msg::RobotState>& v) const {
    std::lock_guard lock(mutex);
    return v.size();
  }
  template <class T>
  std::vector<T> copy(const std::vector<T>& v) const {
    std::lock_guard lock(mutex);
    return v;
  }

 private:
  template <class T>
  void keep(const char* port, std::vector<T>& into) {
    create_subscription<T>(port, {.depth = 64}, [this, &into](Sample<T>&& s) {
      std::lock_guard lock(mutex);
      into.push_back(*s);
    });
  }
  Result<void, std::string> on_configure() override {
    keep<msg::RobotState>("remote/robot_state", states);
    keep<msg::TeamPlan>("remote/plan", plans);
    keep<msg::TsdfPatch>("remote/patch", patches);
    keep<msg::RobotState>("team_events", lost);
    return {};
  }
};

// The process id the domain and partition come from: ours, or the parent's in the child of
// AKilledRobotProcessIsReportedLostWhenItsLeaseRunsOut.
inline uint32_t test_pid() {
  // NOLINTNEXTLINE(concurrency-mt-unsafe): getenv is read before any thread starts
  if (const char* parent = std::getenv("SCANCREW_DDS_TEST_CHILD"))
    return static_cast<uint32_t>(std::strtoul(parent, nullptr, 10));
  return static_cast<uint32_t>(::getpid());
}
inline uint32_t test_domain() {
  return 10 + test_pid() % 200;
}
inline std::string test_partition() {
  return "scancrew_test_" + std::to_string(test_pid());
}

// One robot (or station, id 0) process: a launch running on its own thread.
class Robot {
 public:
  // extra: more bridge parameters, as YAML flow-mapping entries (", key: value"); top: more
  // top-level sections of the launch file ("security: {keys: DIR}\n").
  Robot(uint32_t id, const std::string& extra,
        const std::string& topics = "[robot_state, plan, patch]", const std::string& top = "") {
    const std::string robots = id == 0 ? ""
                                       : "robots:\n  - {id: " + std::to_string(id) +
                                             ", namespace: r" + std::to_string(id) + "}\n";
    const std::string text =
        "clock: wall\nexecutor: {type: single_threaded}\nrun: {duration_s: 0}\n" + top + robots +
        "components:\n"
        "  - {name: source, type: test_dds_source}\n"
        "  - name: bridge\n"
        "    type: dds_bridge\n"
        "    params: {domain_id: " +
        std::to_string(test_domain()) + ", partitions: [" + test_partition() +
        "], transport: loopback, intraprocess: false, team_ids: [0, 1, 2, 3, 4],"
        " export_topics: " +
        topics + ", import_topics: " + topics +
        ", depth_robot_state: 400, liveliness_lease_s: 0.5" + extra +
        "}\n"
        "  - {name: sink, type: test_dds_sink}\n";
    auto launch = Launch::from_string(text, "robot" + std::to_string(id) + ".yaml");
    if (!launch) {
      std::string all;
      for (const auto& e : launch.error()) all += e + "\n";
      ADD_FAILURE() << all;
      return;
    }
    launch_ = std::move(launch).value();
    thread_ = std::thread([this] {
      launch_->run();
      done_.store(true);
    });
  }
  ~Robot() { stop(); }
  Robot(const Robot&) = delete;
  Robot& operator=(const Robot&) = delete;

  bool ok() const { return launch_ != nullptr; }
  void stop() {
    if (!thread_.joinable()) return;
    while (!done_.load()) {  // run() clears a stop requested before it started
      launch_->request_stop();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    thread_.join();
  }
  void destroy() {
    stop();
    launch_.reset();
  }

  Source& source() { return *launch_->find_component<Source>(); }
  DdsBridge& bridge() { return *launch_->find_component<DdsBridge>(); }
  Sink& sink() { return *launch_->find_component<Sink>(); }
  bool active() { return ok() && source().active() && bridge().active(); }

 private:
  std::unique_ptr<Launch> launch_;
  std::thread thread_;
  std::atomic<bool> done_{false};
};

// Waits until every robot runs and DDS discovery is complete both ways: each bridge's
// writer and reader of each topic matched the `bridges` bridges that carry it (its own
// included). A volatile reader does not get what was written before it matched the writer.
inline void wait_ready(const std::vector<Robot*>& robots, size_t bridges,
                       const std::vector<std::string>& topics = {"robot_state", "plan", "patch"}) {
  for (Robot* r : robots) {
    ASSERT_TRUE(r->ok());
    ASSERT_TRUE(wait_until([&] { return r->active(); })) << "a launch did not start";
  }
  for (Robot* r : robots)
    for (const std::string& t : topics)
      for (const bool exported : {true, false})
        ASSERT_TRUE(wait_until([&] { return r->bridge().matched(t, exported) >= bridges; }))
            << "DDS discovery on loopback did not match '" << t << "' ("
            << (exported ? "writer" : "reader") << ")";
}

// The import counters of a bridge, for failure messages.
inline std::string describe(Robot& r) {
  const BridgeStats s = r.bridge().stats();
  std::string out = "taken " + std::to_string(s.taken) + " inbox " + std::to_string(s.inbox) + ": ";
  for (const TopicCounters& t : s.topics)
    out +=
        t.local +
        (t.exported ? " sent " + std::to_string(t.sent_samples)
                    : " received " + std::to_string(t.received_samples) + " delivered " +
                          std::to_string(t.delivered) + " own " + std::to_string(t.own_ignored)) +
        "; ";
  return out;
}

inline const TopicCounters& counters(const BridgeStats& s, const std::string& name, bool exported) {
  const TopicCounters* c = s.find(name, exported);
  EXPECT_NE(c, nullptr) << name;
  static const TopicCounters none;
  return c != nullptr ? *c : none;
}

// A bare Fast DDS participant writing raw Envelopes (or raw bytes) on a bridge topic: the
// hostile peer of the bad-input test.
class RawPeer {
 public:
  // announces robot `announce` at discovery, as a bridge does (none: nullopt); writes on the
  // DDS topic `topic`; security: the participant's DDS-Security properties (none: plain)
  explicit RawPeer(std::optional<uint32_t> announce = 3,
                   const std::vector<std::pair<std::string, std::string>>& security = {},
                   const std::string& topic = "sc/robot_state") {
    fdds::DomainParticipantQos pqos;
    pqos.name("scancrew_test_raw_peer");
    for (const auto& [name, value] : security)
      pqos.properties().properties().emplace_back(name, value);
    if (announce) pqos.user_data().data_vec(participant_user_data(*announce, {test_partition()}));
    pqos.transport().use_builtin_transports = false;
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList.emplace_back("127.0.0.1");
    udp->maxInitialPeersRange = 32;  // as the bridges
    pqos.transport().user_transports.push_back(udp);
    eprosima::fastrtps::rtps::Locator_t peer;
    eprosima::fastrtps::rtps::IPLocator::setIPv4(peer, "127.0.0.1");
    pqos.wire_protocol().builtin.initialPeersList.push_back(peer);
    participant_ =
        fdds::DomainParticipantFactory::get_instance()->create_participant(test_domain(), pqos);
    if (participant_ == nullptr) return;  // refused (security: bad files)
    type_.register_type(participant_);
    topic_ = participant_->create_topic(topic, type_.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    fdds::PublisherQos pub_qos;
    pub_qos.partition().push_back(test_partition().c_str());
    publisher_ = participant_->create_publisher(pub_qos);
    fdds::DataWriterQos wq = publisher_->get_default_datawriter_qos();
    wq.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    wq.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    wq.history().depth = 100;
    writer_ = publisher_->create_datawriter(topic_, wq);
  }
  ~RawPeer() {
    if (participant_ == nullptr) return;
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
  RawPeer(const RawPeer&) = delete;
  RawPeer& operator=(const RawPeer&) = delete;

  // Whether the participant and its writer exist (security may refuse either).
  bool ok() const { return participant_ != nullptr && writer_ != nullptr; }
  size_t matched() const {
    if (writer_ == nullptr) return 0;
    fdds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return static_cast<size_t>(status.current_count);
  }
  bool write(uint32_t version, uint32_t robot, uint64_t seq, const std::string& type,
             std::vector<uint8_t> payload) {
    if (writer_ == nullptr) return false;
    scancrew::dds::Envelope e;
    e.format_version(version);
    e.robot_id(robot);
    e.seq(seq);
    e.type_name(type);
    e.payload(std::move(payload));
    return writer_->write(&e);
  }

 private:
  fdds::DomainParticipant* participant_ = nullptr;
  fdds::TypeSupport type_{new scancrew::dds::EnvelopePubSubType()};
  fdds::Topic* topic_ = nullptr;
  fdds::Publisher* publisher_ = nullptr;
  fdds::DataWriter* writer_ = nullptr;
};

inline std::vector<uint8_t> state_bytes(uint32_t header_robot, uint32_t path_index) {
  msg::RobotState s;
  s.header.robot_id = header_robot;
  s.header.seq = path_index;
  s.path_index = path_index;
  return msg::encode(s);
}

}  // namespace scancrew::dds_bridge::testing
