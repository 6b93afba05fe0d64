#pragma once

// `scancrew bench dds`: latency and throughput of the team network, with and without
// DDS-Security, for scancrew's bridge and for plain Fast DDS side by side (figures:
// docs/results/dds.md).
//
// Systems (a pair each: one sender, one receiver, both in this process so one steady clock
// times them):
//   bridge   two launches with a dds_bridge each: robot 1's exports `patch`, robot 2's
//            imports it; a bench component publishes msg::TsdfPatch on /r1/patch (its `data`
//            holds the payload) and another takes /r2/remote/patch (bridge_pair.cpp);
//   fastdds  two bare Fast DDS participants, a writer and a reader of the bridge's Envelope
//            type (components/dds_bridge/idl) with the bridge's writer and reader QoS
//            (fastdds_pair.cpp).
// Both over UDPv4 on 127.0.0.1 (the bridge's `transport: loopback`), Fast DDS's
// intra-process delivery off for the whole process, so every sample goes through the
// transport as between hosts. Security on: a team's keys made in a temporary folder
// (init_team_keys, add_place_keys for robot_1 and robot_2), the bridges' `security:` block,
// security_properties() for the two Fast DDS participants.
//
// Latency: one message in flight; the sender writes its send time (steady clock) in the
// payload's first 8 bytes, the receiver takes the difference. The next message leaves a
// random 2–4 ms after the previous one arrived (so nothing queues, and the bridge's 2 ms
// import poll is met at every phase), after an unrecorded warm-up of 20. A message not
// arrived within 2 s is waited for no longer (it still counts if it comes); the third such
// ends the case, and what was not sent counts as lost.
// Throughput: bursts of `burst` messages of 64 KiB written back to back, at most `window`
// (default: `depth`) unreceived (a reliable keep-last writer may drop an unacknowledged sample when
// more are written), each timed from the first write to the last arrival; the median burst's rate.
// Each case also reports the UDP datagrams the kernel dropped for a full receive buffer
// meanwhile (/proc/net/snmp RcvbufErrors: repaired by the reliable protocol, they cost time).
//
// Thread safety: run from one thread. Allocation: the bench allocates freely; its figures are
// the systems' own.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace scancrew::bench {

struct DdsBenchOptions {
  bool json = false;    // one JSON object on stdout instead of tables
  bool quick = false;   // 64 B and 64 KiB, 100 latency samples, a burst of 100 (CI)
  int samples = 0;      // latency messages per case; 0: 1000 (quick: 100)
  int burst = 0;        // messages per throughput burst; 0: 500 (quick: 100)
  int bursts = 0;       // throughput bursts (the median is reported); 0: 3 (quick: 1)
  uint32_t depth = 50;  // keep-last depth of the writer and reader (the bridge's depth_patch)
  // throughput: messages unreceived at most; 0: depth (more could be dropped by the writer)
  uint32_t window = 0;
  std::vector<size_t> payload_bytes;  // empty: 64 B, 4 KiB, 64 KiB, 1 MiB (quick: 64 B, 64 KiB)
  size_t burst_payload_bytes = 64 << 10;
  // the bridges' import poll (dds_bridge's poll_period_s; its default): a received sample
  // waits for the next poll, half a period on average
  double bridge_poll_period_s = 0.002;
};

struct DdsLatencyResult {
  std::string system;  // bridge | fastdds
  bool secure = false;
  size_t payload_bytes = 0;
  size_t messages = 0;  // sent (after the warm-up)
  size_t received = 0;
  double p50_us = 0, p99_us = 0, max_us = 0;
  // UDP datagrams the kernel dropped for a full receive buffer during the case, counted for
  // the whole network namespace (other processes' too); -1: unknown
  int64_t rcvbuf_drops = -1;
  size_t lost() const { return messages - received; }
};

struct DdsThroughputResult {
  std::string system;
  bool secure = false;
  size_t payload_bytes = 0;
  size_t messages = 0;  // over every burst
  size_t received = 0;
  size_t bursts = 0;
  double seconds = 0;         // the median burst's, first write to last arrival
  double messages_per_s = 0;  // the median burst's
  double mb_per_s = 0;        // payload bytes, 10^6 per MB
  int64_t rcvbuf_drops = -1;  // over every burst, as DdsLatencyResult's
  size_t lost() const { return messages - received; }
};

// Runs every case and prints the tables (or the JSON object). Returns 0 when every message
// of every case arrived, 1 when some were lost, 2 when a pair could not be set up; the
// process ends with status 3 when setting a pair up or tearing it down outlives its bound
// (120 s, 60 s: a Fast DDS hang).
int run_dds_bench(const DdsBenchOptions& options);

}  // namespace scancrew::bench
