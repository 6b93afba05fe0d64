#pragma once

// The bridge's counters: per bridged topic, what went out and came in over DDS, what the
// link model dropped and what the checks rejected (the thesis' "data exchanged" metric,
// 5.4, is the sum of sent_bytes over the robots, or of received_bytes at a station).
// Bytes are CDR sizes of the envelope (idl/envelope.idl): payload plus about 50 bytes;
// RTPS headers, fragmentation, acknowledgements and resends are not counted.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace scancrew::dds_bridge {

// Why an incoming sample was refused. Each kind is logged once per bridge, then counted.
enum class Reject : uint8_t {
  kFormatVersion,  // the sender speaks another msg::kMessageFormatVersion
  kUnknownType,    // a type name that is no wire message of this build
  kTypeMismatch,   // a wire message, but not the type of this topic
  kOversize,       // a payload over max_sample_bytes
  kUnknownRobot,   // a robot id (envelope or message header) not in the team
  kMalformed,      // the payload does not decode (truncated, trailing bytes, bad counts)
  kForgedSender,   // a robot id that the sending participant did not announce at discovery
};
inline constexpr size_t kRejectKinds = 7;
std::string_view to_string(Reject reject);

struct TopicCounters {
  std::string name;       // as listed in the launch file, e.g. "robot_state"
  std::string local;      // the local topic, e.g. "/r1/robot_state" or "/r1/remote/robot_state"
  std::string dds_topic;  // e.g. "sc/robot_state"
  std::string type_name;  // e.g. "scancrew/RobotState"
  bool exported = false;  // true: local -> DDS; false: DDS -> local
  // export side
  uint64_t sent_samples = 0, sent_bytes = 0;
  uint64_t send_failures = 0;  // oversize or a failed DDS write
  // import side
  uint64_t received_samples = 0, received_bytes = 0;  // taken from DDS (own samples excluded)
  uint64_t delivered = 0;                             // published locally
  uint64_t own_ignored = 0;                           // our own samples (loopback)
  uint64_t duplicates = 0;  // a sequence number not above the sender's last one (a resend)
  uint64_t dropped_partition = 0, dropped_loss = 0, dropped_saturated = 0;  // link model
  uint64_t dropped_inbox = 0;  // the inbox between DDS and the executor was full
  std::array<uint64_t, kRejectKinds> rejected{};

  uint64_t rejected_total() const;
  uint64_t link_dropped() const { return dropped_partition + dropped_loss + dropped_saturated; }
};

struct BridgeStats {
  std::vector<TopicCounters> topics;
  uint64_t peers_lost = 0;  // lost reports published (one per robot and loss)
  uint64_t taken = 0;       // samples taken from DDS readers (all topics, own included)
  uint64_t inbox = 0;       // of those, waiting for the executor now

  const TopicCounters* find(std::string_view name, bool exported) const;
  uint64_t sent_bytes() const;
  uint64_t received_bytes() const;
  uint64_t rejected(Reject reject) const;
};

}  // namespace scancrew::dds_bridge
