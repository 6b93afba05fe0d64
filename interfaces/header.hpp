#pragma once

// The header every message carries, so latency can be traced through the graph and
// across robots.

#include <cstdint>

namespace scancrew::msg {

inline constexpr int64_t kStampUnset = INT64_MIN;

struct Header {
  uint32_t robot_id = 0;           // the publishing robot (0 for a station or a test)
  uint64_t seq = 0;                // per publisher, starts at 1, no gaps on the publisher side
  int64_t stamp_ns = kStampUnset;  // sim or wall time of the data (capture time), ns
  int64_t publish_mono_ns = 0;     // monotonic time of publish() on the publishing machine, ns
};

}  // namespace scancrew::msg
