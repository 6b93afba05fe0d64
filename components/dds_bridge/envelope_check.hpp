#pragma once

// The checks an incoming envelope must pass before the bridge decodes it, and the one
// after decoding (the message header's robot id). Pure functions: no DDS, no logging.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "components/dds_bridge/bridge_stats.hpp"
#include "components/dds_bridge/dds_link.hpp"

namespace scancrew::dds_bridge {

struct EnvelopeRules {
  uint32_t format_version = 0;  // msg::kMessageFormatVersion
  std::vector<uint32_t> team;   // robot ids that may send (sorted or not); empty: anyone
  size_t max_sample_bytes = 0;  // payload limit
};

// nullopt when the envelope may be decoded as `topic_type`; else why not, with a detail
// for the log in *detail.
std::optional<Reject> check_envelope(const WireEnvelope& envelope, std::string_view topic_type,
                                     const EnvelopeRules& rules, std::string* detail);

bool in_team(const EnvelopeRules& rules, uint32_t robot_id);

}  // namespace scancrew::dds_bridge
