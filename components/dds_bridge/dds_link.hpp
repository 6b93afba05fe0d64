#pragma once

// DdsLink: the Fast DDS side of the bridge, behind a pimpl so Fast DDS headers stay in
// dds_link.cpp. One DomainParticipant; one DataWriter or DataReader of the Envelope type
// (idl/envelope.idl) per bridged topic, each with its own QoS; and a presence topic by
// which bridges learn each other's robot ids and notice a peer's loss (DDS liveliness).
//
// Presence: every link writes one Envelope (type "scancrew/Presence", empty payload) on
// kPresenceTopic, reliable and transient-local, with AUTOMATIC liveliness and the
// configured lease. A peer's presence writer that loses its liveliness (its process died
// or hangs) or is unmatched (its participant left) reports that robot lost; one that
// becomes alive again reports it back. Reports happen on transitions only.
//
// Thread safety: set-up (create, add_writer, add_reader, announce) from one thread; write()
// from any thread. The callbacks run on Fast DDS threads, possibly concurrently: they must
// be thread safe and must not call back into the link. After close() (or the destructor)
// no callback runs any more.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.hpp"
#include "core/result.hpp"

namespace scancrew::dds_bridge {

inline constexpr std::string_view kPresenceTopic = "sc/_presence";
inline constexpr std::string_view kPresenceType = "scancrew/Presence";
// The lockstep's topic (dds_bridge_lockstep.cpp), written and read by every bridge of a team
// split over processes.
inline constexpr std::string_view kLockstepTopic = "sc/_lockstep";

// qos_<topic>: reliable | best_effort
enum class Reliability : uint8_t { kReliable, kBestEffort };
inline constexpr EnumNames<Reliability, 2> kReliabilityNames = {
    {{Reliability::kReliable, "reliable"}, {Reliability::kBestEffort, "best_effort"}}};

struct DdsTopicQos {
  Reliability reliability = Reliability::kReliable;
  uint32_t depth = 10;           // keep-last history depth (writer and reader)
  bool transient_local = false;  // a late joiner gets the last `depth` samples
};

// loopback: UDPv4 on 127.0.0.1 only (tests, one machine); shm: shared memory plus UDPv4
// loopback; udp: UDPv4 on every interface; builtin: Fast DDS's defaults (SHM + UDPv4).
enum class Transport : uint8_t { kLoopback, kShm, kUdp, kBuiltin };
inline constexpr EnumNames<Transport, 4> kTransportNames = {{{Transport::kLoopback, "loopback"},
                                                             {Transport::kShm, "shm"},
                                                             {Transport::kUdp, "udp"},
                                                             {Transport::kBuiltin, "builtin"}}};

struct DdsLinkConfig {
  uint32_t domain_id = 0;
  std::vector<std::string> partitions;  // DDS partitions of every writer and reader
  Transport transport = Transport::kLoopback;
  std::vector<std::string> initial_peers;  // IPv4 addresses for unicast discovery
  // participants per initial peer (and on loopback) that unicast discovery reaches: Fast DDS
  // numbers the participants of a host 0, 1, 2, ... (never reusing a number in a process)
  uint32_t initial_peers_range = 32;
  double liveliness_lease_s = 2.0;  // a silent peer is lost after this
  // Fast DDS's intra-process shortcut between participants of one process. false turns it
  // off for the whole process (a library-wide setting), so that bridges composed in one
  // process (tests) talk over the configured transport as separate processes would.
  bool intraprocess = true;
  std::string participant_name;
  uint32_t robot_id = 0;  // announced at discovery and written in the presence sample
  // DDS-Security (team_keys.hpp): the participant's properties (plugins, certificates,
  // governance, permissions); empty: plain DDS. With security, a peer's announced robot id
  // counts only when its authenticated certificate is that robot's place of security_team
  // (place_subject(security_team, place_name(id, simulator_id))).
  std::vector<std::pair<std::string, std::string>> security_properties;
  std::string security_team;
  uint32_t simulator_id = 65535;
};

// An envelope as it travels (fields of idl/envelope.idl).
// A received envelope's sender_robot_id when its participant announced no robot id.
inline constexpr uint32_t kUnknownSender = 0xffffffffu;

struct WireEnvelope {
  uint32_t format_version = 0;
  uint32_t robot_id = 0;
  uint64_t seq = 0;
  int64_t stamp_ns = 0;
  std::string type_name;
  std::vector<uint8_t> payload;
  // Received only (not on the wire): the robot id that the sending participant announced at
  // discovery (its user data, participant_user_data()), kUnknownSender if none or if another
  // participant in the domain had announced that id first. check_envelope() refuses an
  // envelope whose robot_id is not this one.
  uint32_t sender_robot_id = kUnknownSender;
  // The robot id the sending participant announced, whether or not it holds it (a restarted
  // robot's new process before the old one left): the lockstep counts such a sample as
  // received (refused, it will not come again).
  uint32_t claimed_robot_id = kUnknownSender;
};

// A bridge participant's user data: who it is and its partitions, announced at discovery
// (before its endpoints are matched), so that a sample is tied to its sending participant.
std::vector<uint8_t> participant_user_data(uint32_t robot_id,
                                           const std::vector<std::string>& partitions);
// The robot id of a participant's user data; nullopt if it is not a bridge's or if its
// partitions are not these (another team sharing the domain).
std::optional<uint32_t> robot_of_user_data(const std::vector<uint8_t>& user_data,
                                           const std::vector<std::string>& partitions);

class DdsLink {
 public:
  struct Callbacks {
    // A sample taken from reader `reader` (index from add_reader); wire_bytes is its CDR size.
    std::function<void(size_t reader, WireEnvelope&& envelope, size_t wire_bytes)> on_sample;
    // A peer robot lost (alive = false) or back (alive = true); `why` says how. Presence
    // counts only from the participant that announced the robot at discovery.
    // Called under the link's peer lock, so events come in order: the callback must not call
    // into the link.
    std::function<void(uint32_t robot_id, bool alive, std::string_view why)> on_peer;
    // Another participant than the last one announced the robot (a restarted robot's new
    // process): before any of its samples. Under the peer lock, like on_peer.
    std::function<void(uint32_t robot_id)> on_new_process;
    // A problem worth one log line (incompatible QoS, a sample DDS could not read).
    std::function<void(const std::string& message)> on_warning;
  };

  static Result<std::unique_ptr<DdsLink>, std::string> create(const DdsLinkConfig& config,
                                                              Callbacks callbacks);
  ~DdsLink();
  DdsLink(const DdsLink&) = delete;
  DdsLink& operator=(const DdsLink&) = delete;

  // Set-up; each returns the index of the new endpoint.
  Result<size_t, std::string> add_writer(const std::string& dds_topic, const DdsTopicQos& qos);
  Result<size_t, std::string> add_reader(const std::string& dds_topic, const DdsTopicQos& qos);
  // Writes the presence sample (after set-up; again after a reconnect is harmless).
  Result<void, std::string> announce();

  // Writes on writer `writer`; returns the CDR size written.
  // The payload is moved into DDS and handed back (unchanged) for reuse.
  Result<size_t, std::string> write(size_t writer, WireEnvelope& envelope);
  // Matched remote endpoints of writer / reader `index` (tests wait on these).
  size_t writer_matches(size_t writer) const;
  size_t reader_matches(size_t reader) const;
  // Peers whose presence this link has seen alive.
  size_t peers_alive() const;

  // Detaches the listeners and deletes every DDS entity (idempotent).
  void close();

  struct Impl;  // opaque: the Fast DDS entities (dds_link.cpp)

 private:
  explicit DdsLink(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::dds_bridge
