// scancrew side of `scancrew bench ipc`: loan -> publish -> callback, same thread
// (publish then spin_some) and cross thread (an executor thread asleep on its
// condition variable until the sample arrives).

#include <atomic>
#include <chrono>
#include <cstddef>
#include <thread>
#include <vector>

#include "bench/ipc/cpu_pinning.hpp"
#include "bench/ipc/ipc_bench.hpp"
#include "bench/ipc/latency_samples.hpp"
#include "executors/executor.hpp"
#include "executors/graph.hpp"
#include "executors/publisher.hpp"
#include "executors/subscription.hpp"

namespace scancrew::bench {

namespace {

struct Blob {
  static constexpr const char* kTypeName = "scancrew/bench/Blob";
  msg::Header header;
  int64_t t0_ns = 0;            // monotonic time just before loan()
  std::vector<std::byte> data;  // payload_bytes, sized once per slot at warm-up
};

constexpr size_t kPoolSize = 4;

// Gives every slot its payload capacity, so the measured loop allocates nothing.
void warm_pool(Publisher<Blob>& pub, size_t payload) {
  std::vector<Loan<Blob>> loans;
  for (size_t i = 0; i < kPoolSize; ++i) {
    auto loan = pub.loan();
    if (!loan) break;
    (*loan)->data.resize(payload);
    loans.push_back(std::move(loan).value());
  }
}

IpcResult run_case(size_t payload, bool cross_thread, const IpcOptions& options) {
  Graph graph(std::make_shared<WallClock>());
  CallbackGroup group("bench", CallbackGroup::Type::kMutuallyExclusive);
  auto topic = graph.topic<Blob>("/bench/blob", kPoolSize).value();
  Publisher<Blob> pub(topic, 0, &graph.clock(), nullptr);
  LatencySamples samples(static_cast<size_t>(options.samples));
  std::atomic<uint64_t> received{0};
  std::atomic<bool> measuring{false};
  Subscription<Blob> sub(
      topic, {.depth = 2},
      [&](Sample<Blob>&& s) {
        if (measuring.load(std::memory_order_relaxed)) samples.add(monotonic_now_ns() - s->t0_ns);
        received.fetch_add(1, std::memory_order_release);
      },
      group, nullptr);
  SingleThreadedExecutor executor(int64_t{options.spin_us} * 1000);
  executor.add(sub);
  warm_pool(pub, payload);
  std::thread spinner;
  if (cross_thread) {
    pin_to_cpu(0);
    spinner = std::thread([&] {
      pin_to_cpu(1);
      executor.spin();
    });
  }

  IpcResult result{"scancrew", cross_thread ? "cross_thread" : "same_thread", payload};
  result.spin_us = options.spin_us;
  const int warmup = 500;  // unrecorded: the receiving thread and core settle
  for (int i = 0; i < warmup + options.samples; ++i) {
    measuring.store(i >= warmup, std::memory_order_relaxed);
    const uint64_t before = received.load(std::memory_order_acquire);
    const int64_t t0 = monotonic_now_ns();
    auto loan = pub.loan();
    if (!loan) {
      ++result.lost;
      continue;
    }
    (*loan)->t0_ns = t0;
    (void)pub.publish(std::move(*loan));
    if (!cross_thread) {
      executor.spin_some();
      // counted like the peers' same-thread cases: a sample not taken by the spin is lost
      if (received.load(std::memory_order_acquire) == before) ++result.lost;
    } else {
      const int64_t give_up = monotonic_now_ns() + 1'000'000'000;
      while (received.load(std::memory_order_acquire) == before && monotonic_now_ns() < give_up) {
      }
      if (received.load() == before) ++result.lost;
      std::this_thread::sleep_for(std::chrono::microseconds(options.gap_us));
    }
  }
  if (cross_thread) {
    executor.stop();
    spinner.join();
    unpin();
  }
  executor.remove(sub);
  samples.summarise(result);
  return result;
}

}  // namespace

std::vector<IpcResult> bench_scancrew(const IpcOptions& options) {
  std::vector<IpcResult> results;
  for (bool cross : {false, true})
    for (size_t payload : options.payload_bytes)
      results.push_back(run_case(payload, cross, options));
  return results;
}

}  // namespace scancrew::bench
