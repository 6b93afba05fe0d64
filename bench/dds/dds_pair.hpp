#pragma once

// The two ends of one `scancrew bench dds` case (dds_bench.hpp): a sender and a receiver in
// this process, over a system (the bridge, plain Fast DDS) with or without DDS-Security.
//
// A bench payload starts with a 16-byte header: the send time (steady clock, ns, int64),
// the phase and the message's index in it (uint32 each), in host byte order (one process).

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace scancrew::bench {

inline constexpr size_t kDdsBenchHeaderBytes = 16;

// Writes the header into the first kDdsBenchHeaderBytes of `payload` (which holds at least
// that), with the send time taken now.
void stamp_payload(std::span<uint8_t> payload, uint32_t phase, uint32_t index);

// What the receiving end saw of the current phase: how many arrived, their one-way delays,
// the last arrival's time. Samples of another phase (late ones) are counted apart.
// Thread safety: arrived() from any thread (the receiving side's), the rest from the bench
// thread. arrived() locks a mutex and, once per phase, may allocate (reserve in start_phase).
class Arrivals {
 public:
  // A new phase: forgets the last one's arrivals; `expected` messages are reserved for.
  void start_phase(uint32_t phase, size_t expected);
  // A payload arrived (now): recorded if it carries the current phase.
  void arrived(std::span<const uint8_t> payload);
  // Waits until `n` messages of the phase arrived, up to timeout_s; whether they did.
  bool wait_for(size_t n, double timeout_s);
  size_t count() const;
  size_t stale() const;  // payloads of an earlier phase, or too short to carry a header
  int64_t last_arrival_ns() const;
  // The one-way delays of the phase's arrivals, in arrival order.
  std::vector<int64_t> delays_ns() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  uint32_t phase_ = 0;
  std::vector<int64_t> delays_ns_;
  size_t stale_ = 0;
  int64_t last_arrival_ns_ = 0;
};

// One case's set-up.
struct PairSetup {
  uint32_t domain_id = 0;
  std::string partition;                // the DDS partition of every writer and reader
  uint32_t depth = 50;                  // keep-last depth, writer and reader
  double bridge_poll_period_s = 0.002;  // the bridges' poll_period_s (their default)
  // a team key folder with places robot_1 (sender) and robot_2 (receiver), each granted
  // kDdsBenchTopic and the bridges' presence topic; empty: no security
  std::string keys_dir;
};

// The DDS topic both systems use (the bridge's `patch` with its default prefix).
inline constexpr const char* kDdsBenchTopic = "sc/patch";

// A sender and a receiver that discovered each other (writer and reader matched).
// Thread safety: send() from one thread; arrivals reach the Arrivals given at creation from
// the system's own threads until the pair is destroyed.
class DdsPair {
 public:
  virtual ~DdsPair() = default;
  // Sends one message of payload_bytes (>= kDdsBenchHeaderBytes), stamped just before it is
  // handed to the system. False when it could not be sent within a bounded wait.
  virtual bool send(size_t payload_bytes, uint32_t phase, uint32_t index) = 0;
};

// Two launches with a dds_bridge each (bridge_pair.cpp); waits up to 30 s for discovery.
Result<std::unique_ptr<DdsPair>, std::string> make_bridge_pair(const PairSetup& setup,
                                                               Arrivals& arrivals);
// Two bare Fast DDS participants (fastdds_pair.cpp); waits up to 30 s for discovery.
Result<std::unique_ptr<DdsPair>, std::string> make_fastdds_pair(const PairSetup& setup,
                                                                Arrivals& arrivals);

}  // namespace scancrew::bench
