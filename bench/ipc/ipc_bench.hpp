#pragma once

// `scancrew bench ipc`: publish -> callback latency for payloads from 64 B to 16 MB,
// delivered on the publishing thread and to another thread, for scancrew's runtime, for
// Fast DDS (intra-process, data-sharing, loans, plain type) and for iceoryx (RouDi in this
// process, loaned shared-memory chunks) in the same binary.
// Method and recorded figures: docs/bench_ipc.md.

#include <cstddef>
#include <string>
#include <vector>

namespace scancrew::bench {

struct IpcOptions {
  int samples = 2000;  // measured messages per case (after warm-up)
  bool json = false;   // one JSON object on stdout instead of a table
  std::vector<size_t> payload_bytes = {64, 4096, 256 << 10, 1 << 20, 4 << 20, 16 << 20};
  int gap_us = 50;  // pause between messages, so the receiver is asleep when one comes
  int spin_us = 0;  // scancrew's executor: bounded spin before blocking (Executor spin_ns)
  bool fastdds_intraprocess =
      true;  // Fast DDS INTRAPROCESS_FULL (library default) or OFF (data-sharing path)
};

struct IpcResult {
  std::string system;  // scancrew | fastdds | iceoryx
  std::string mode;    // same_thread | cross_thread
  size_t payload_bytes = 0;
  double p50_us = 0, p99_us = 0, max_us = 0;
  size_t lost = 0;  // messages that never arrived (bounded wait)
  int spin_us = 0;  // receiver spin before blocking (scancrew only)
};

std::vector<IpcResult> bench_scancrew(const IpcOptions& options);
std::vector<IpcResult> bench_fastdds(const IpcOptions& options);
// Starts RouDi inside this process for the call's duration; every case of a call fails
// (lost = samples) when another RouDi is running on this machine.
std::vector<IpcResult> bench_iceoryx(const IpcOptions& options);

// Runs every case and prints the table or the JSON object. Returns the exit status.
int run_ipc_bench(const IpcOptions& options);

}  // namespace scancrew::bench
