#include "components/dds_bridge/bridge_stats.hpp"

#include <numeric>

namespace scancrew::dds_bridge {

std::string_view to_string(Reject reject) {
  switch (reject) {
    case Reject::kFormatVersion:
      return "message format version";
    case Reject::kUnknownType:
      return "unknown type";
    case Reject::kTypeMismatch:
      return "type mismatch";
    case Reject::kOversize:
      return "oversized";
    case Reject::kUnknownRobot:
      return "unknown robot id";
    case Reject::kMalformed:
      return "malformed";
    case Reject::kForgedSender:
      return "forged sender";
  }
  return "?";
}

uint64_t TopicCounters::rejected_total() const {
  return std::accumulate(rejected.begin(), rejected.end(), uint64_t{0});
}

const TopicCounters* BridgeStats::find(std::string_view name, bool exported) const {
  for (const TopicCounters& t : topics)
    if (t.name == name && t.exported == exported) return &t;
  return nullptr;
}

uint64_t BridgeStats::sent_bytes() const {
  uint64_t sum = 0;
  for (const TopicCounters& t : topics) sum += t.sent_bytes;
  return sum;
}

uint64_t BridgeStats::received_bytes() const {
  uint64_t sum = 0;
  for (const TopicCounters& t : topics) sum += t.received_bytes;
  return sum;
}

uint64_t BridgeStats::rejected(Reject reject) const {
  uint64_t sum = 0;
  for (const TopicCounters& t : topics) sum += t.rejected[static_cast<size_t>(reject)];
  return sum;
}

}  // namespace scancrew::dds_bridge
