#pragma once

// DdsBridge: carries chosen topics between robot and station processes over Fast DDS
// (ARCHITECTURE.md; thesis 3.1 centralized and 4.1 distributed architectures): robot state,
// team plans, patch lists, requests, replies and patches, depth and pose to a station,
// mission status. docs/dds_bridge.md is the user guide.
//
// Export (local -> DDS): a subscription per topic encodes each message with the codec of
// interfaces/codec.hpp into an Envelope (idl/envelope.idl: format version, robot id,
// sequence, stamp, type name, payload) and writes it on the DDS topic "sc/<name>".
// Import (DDS -> local): a DDS listener queues each envelope in a bounded inbox; a timer on
// the executor thread (every poll_period_s) checks it (envelope_check.hpp), applies the link
// model (link_model.hpp), and when it is due decodes it straight into a loaned sample and
// forwards it whole (the sender's robot id, sequence and stamp) on the local port
// "remote/<name>" (remappable in the launch file). Samples with our own robot id are ignored
// (no loop). Nothing is published from a DDS thread.
// Peers: a bridge announces itself on a presence topic with AUTOMATIC liveliness; when a
// teammate's process dies (its lease runs out) or leaves, a msg::RobotState with mode kLost
// and that robot's id in its header is published on the port "team_events" (once per loss).
//
// Topic names may hold "{team}" (every robot of the launch) or "{others}" (every robot but
// this bridge's): "/{others}/patch" imports /r2/patch and /r3/patch in robot 1's process.
// An absolute import lands on its own name (a process of the team split over processes
// sees its teammates' topics where a one-process run has them).
// Lockstep (lockstep: leader | follower): the bridges of a team split over processes step
// their sim clocks together (step_gate(), dds_bridge_lockstep.cpp, docs/processes.md).
//
// Thread safety: stats() and the test accessors may be called from any thread. The
// component's callbacks must run in a mutually exclusive group (the default).

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <queue>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "components/dds_bridge/bridge_stats.hpp"
#include "components/dds_bridge/dds_link.hpp"
#include "components/dds_bridge/envelope_check.hpp"
#include "components/dds_bridge/link_model.hpp"
#include "executors/component.hpp"
#include "executors/launch.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::dds_bridge {

// The names a bridged topic name stands for: "{team}", "{others}" or "{self}" (one of them,
// a whole segment) replaced by the namespace of every robot of the team, every robot but
// self_id, or self_id's; a name without a placeholder stands for itself.
Result<std::vector<std::string>, std::string> expand_topic_name(const std::string& name,
                                                                const std::vector<TeamMember>& team,
                                                                uint32_t self_id);
// The DDS topic of a bridged name: prefix + the name without its leading '/'.
std::string dds_topic_name(const std::string& prefix, const std::string& name);

struct BridgedTopic {
  std::string name;       // as listed: "robot_state" (relative) or "/team/plan" (absolute)
  std::string key;        // for the per-topic parameters: "robot_state", "team_plan"
  std::string type_name;  // kTypeName; empty: taken from the local graph at configure
  DdsTopicQos qos;
  bool exported = false;
  bool lossy = true;  // the link model's loss applies (link_loss_topics)
};

// lockstep: none | leader (the simulator) | follower (robots, station)
enum class LockstepRole : uint8_t { kNone, kLeader, kFollower };
inline constexpr EnumNames<LockstepRole, 3> kLockstepRoleNames = {
    {{LockstepRole::kNone, "none"},
     {LockstepRole::kLeader, "leader"},
     {LockstepRole::kFollower, "follower"}}};

class DdsBridge final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "Fast DDS bridge: exports and imports topics between robots and a station, with a link "
      "model, counters and robot-loss reports";
  struct Config {
    uint32_t domain_id = 0;
    std::vector<std::string> partitions;         // DDS partitions; empty: the default partition
    Transport transport = Transport::kLoopback;  // (dds_link.hpp)
    std::vector<std::string> initial_peers;
    uint32_t initial_peers_range = 32;        // participants per peer host reached by unicast
    bool intraprocess = true;                 // false: Fast DDS's in-process shortcut off (tests)
    std::vector<BridgedTopic> topics;         // exports, then imports
    std::string dds_prefix = "sc/";           // DDS topic = prefix + name without a leading '/'
    std::string import_prefix = "remote/";    // local port of an import = prefix + name
    std::string lost_port = "team_events";    // where robot-loss reports go ("{lost}": its ns)
    std::vector<uint32_t> team_ids;           // senders accepted; empty: the launch's robots + 0
    uint64_t max_sample_bytes = 64ULL << 20;  // a larger payload is refused (both ways)
    uint32_t inbox_samples = 4096;            // DDS -> executor queue; overflow drops oldest
    uint64_t inbox_bytes = 256ULL << 20;      // and its samples' bytes (overflow drops oldest)
    double poll_period_s = 0.002;             // how often imports are delivered
    double liveliness_lease_s = 2.0;          // a silent peer is reported lost after this
    // the id in this bridge's envelopes; -1: its robot's id (0 for a station)
    int64_t bridge_id = -1;
    uint32_t simulator_id = 65535;  // the simulator process's bridge id (in the default team)
    LockstepRole lockstep = LockstepRole::kNone;
    std::vector<uint32_t> lockstep_followers;  // leader: who follows; empty: the launch's robots
    double lockstep_timeout_s = 120.0;         // wall seconds a step may wait for a peer, then stop
    LinkConfig link;
  };
  static Config read_config(ParamReader& p);

  DdsBridge(ComponentContext context, Config config);
  ~DdsBridge() override;

  BridgeStats stats() const;
  // For tests and tools: DDS matches of a bridged topic (0 when unknown), peers seen alive,
  // and whether the component is active.
  size_t matched(std::string_view name, bool exported) const;
  size_t peers_alive() const;
  bool active() const { return active_now_.load(); }
  // lockstep: leader | follower: the gate Launch::run consults around each step; else null.
  StepGate* step_gate();
  uint32_t bridge_id() const { return self_id_; }

 private:
  class Lockstep;  // dds_bridge_lockstep.cpp
  friend class Lockstep;
  struct Incoming {
    size_t topic = 0;  // index into topics_
    WireEnvelope envelope;
    size_t wire_bytes = 0;
    int64_t arrival_ns = 0;
    bool oversize = false;  // over max_sample_bytes: its payload and type name were not kept
  };
  struct Pending {  // admitted by the link model, waiting for its delivery time
    int64_t deliver_at_ns = 0;
    uint64_t order = 0;  // FIFO among equal times
    Incoming sample;
    bool operator>(const Pending& o) const {
      return deliver_at_ns != o.deliver_at_ns ? deliver_at_ns > o.deliver_at_ns : order > o.order;
    }
  };
  enum class Delivery { kPublished, kPoolExhausted, kRejected };
  // Decodes a payload into a loan and forwards it; kRejected fills *reason.
  using DeliverFn = std::function<Delivery(const WireEnvelope&, Reject* reason)>;
  struct TopicState {
    BridgedTopic spec;
    size_t endpoint = 0;  // DDS writer or reader index
    uint64_t topic_key = 0;
    uint64_t seq = 0;              // export: last sequence number written
    std::vector<uint8_t> scratch;  // export: the encoding buffer
    DeliverFn deliver;             // import
  };
  using MarkKey = std::pair<uint32_t, uint64_t>;  // sender, DDS topic key
  struct PeerEvent {
    uint32_t robot_id = 0;
    bool alive = false;
    std::string why;
  };

  Result<void, std::string> on_configure() override;
  void on_activate() override;
  void on_deactivate() override;
  void on_shutdown() override;

  Result<DdsLinkConfig, std::string> link_config() const;
  DdsLink::Callbacks link_callbacks();
  void queue_sample(size_t reader, WireEnvelope&& envelope, size_t bytes);
  void create_lost_publishers();
  Result<void, std::string> expand_templates();
  std::string local_port(const BridgedTopic& spec) const;
  Result<void, std::string> resolve_type(BridgedTopic& spec);
  Result<void, std::string> add_topic(const BridgedTopic& spec);
  template <class T>
  void add_export(size_t index);
  template <class T>
  void add_import(size_t index);
  void send(size_t index, std::span<const uint8_t> bytes);
  void tick();
  void admit(Incoming&& in);
  bool held_back(Incoming& in);
  Result<void, std::string> make_lockstep();
  void on_sync(WireEnvelope&& envelope);
  void handle_peer(const PeerEvent& event);
  void restart_sender(uint32_t id);
  void reject(TopicCounters& counters, Reject reason, const std::string& detail);
  void warn_once(const std::string& message);

  Config config_;
  uint32_t self_id_ = 0;
  EnvelopeRules rules_;
  std::optional<LinkModel> link_model_;
  std::unique_ptr<DdsLink> link_;
  std::vector<TopicState> topics_;
  std::vector<size_t> topic_of_reader_;  // DDS reader index -> topics_ index (set-up only)
  Publisher<msg::RobotState> lost_pub_;
  std::map<uint32_t, std::shared_ptr<Publisher<msg::RobotState>>> lost_pubs_;  // "{ns}" ports
  uint64_t lost_seq_ = 0;
  std::priority_queue<Pending, std::vector<Pending>, std::greater<>> pending_;
  uint64_t pending_order_ = 0;
  std::vector<Incoming> drained_;  // executor thread: the inbox, swapped out
  std::atomic<bool> active_now_{false};

  // DDS threads -> executor thread
  mutable std::mutex inbox_mutex_;
  std::deque<Incoming> inbox_;
  uint64_t inbox_wire_bytes_ = 0;  // of the samples kept in inbox_
  std::vector<PeerEvent> peer_events_;
  std::vector<uint32_t> restarts_;          // robots whose new process announced itself (restarted)
  std::map<size_t, uint64_t> inbox_drops_;  // per DDS reader
  uint64_t taken_ = 0;

  mutable std::mutex stats_mutex_;  // counters (DDS threads count inbox drops)
  BridgeStats stats_;
  std::array<bool, kRejectKinds> reject_logged_{};
  std::vector<std::string> warned_;

  // lockstep: the driver thread (step gate) <-> DDS threads
  std::unique_ptr<StepGate> lockstep_;  // a Lockstep
  size_t sync_writer_ = 0, sync_reader_ = 0;
  std::mutex sync_mutex_;
  std::condition_variable sync_cv_;
  std::atomic<size_t> data_readers_{SIZE_MAX};  // DDS readers of topics (then the lockstep's)
  std::map<std::pair<uint32_t, size_t>, uint64_t> received_max_;  // per sender and DDS reader
  std::map<uint32_t, msg::StepSync> syncs_;  // the latest StepSync of each peer
  std::set<uint32_t> alive_, lost_;          // peers by presence
  // the executor thread (the driver's, under a step executor): what may be delivered
  std::map<MarkKey, uint64_t> released_;
  std::map<std::pair<uint32_t, size_t>, uint64_t> last_seq_;  // per sender and topic: admitted
  std::vector<Incoming> held_;
};

}  // namespace scancrew::dds_bridge
