#pragma once

// Exact latency samples of one benchmark case, preallocated (recording allocates nothing).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include "bench/ipc/ipc_bench.hpp"
#include "executors/clock.hpp"

namespace scancrew::bench {

class LatencySamples {
 public:
  explicit LatencySamples(size_t capacity) { values_ns_.reserve(capacity); }
  void add(int64_t ns) {
    if (values_ns_.size() < values_ns_.capacity()) values_ns_.push_back(ns);
  }
  size_t size() const { return values_ns_.size(); }
  void clear() { values_ns_.clear(); }
  // Sorts and fills p50/p99/max (µs) of `result`.
  void summarise(IpcResult& result);

 private:
  std::vector<int64_t> values_ns_;
};

// What a peer's writing side and its reading side (take_all on the writer's thread, or the
// reader's thread) share during one case (Fast DDS, iceoryx).
struct DeliveryState {
  explicit DeliveryState(size_t capacity) : samples(capacity) {}
  LatencySamples samples;
  std::atomic<bool> measuring{false};  // false during warm-up: nothing recorded
  std::atomic<uint64_t> received{0};   // samples taken so far
  std::atomic<bool> stop{false};       // ends the reader's thread
};

// The peers' wait for one sample, after its write (Fast DDS, iceoryx): on this thread,
// `take_all` until `received` moves past `before`; across threads, spin until the reader's
// thread moves it, then sleep gap_us. At most 1 s; true when it arrived.
template <class TakeAll>
bool await_delivery(const std::atomic<uint64_t>& received, uint64_t before, bool cross_thread,
                    int64_t gap_us, TakeAll&& take_all) {
  const int64_t give_up = monotonic_now_ns() + 1'000'000'000;
  if (!cross_thread) {
    while (received.load() == before && monotonic_now_ns() < give_up) take_all();
  } else {
    while (received.load(std::memory_order_acquire) == before && monotonic_now_ns() < give_up) {
    }
    std::this_thread::sleep_for(std::chrono::microseconds(gap_us));
  }
  return received.load() != before;
}

}  // namespace scancrew::bench
