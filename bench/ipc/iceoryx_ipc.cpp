// iceoryx side of `scancrew bench ipc`: iceoryx 2.0 (Debian's 2.0.3) with RouDi inside this
// process (iceoryx's "single process" set-up: RouDi's components, RouDi and a
// PoshRuntimeSingleProcess; no daemon), an untyped publisher loaning chunks from RouDi's
// shared-memory pools and an untyped subscriber taking them, zero-copy.
//  - same_thread: publish, then take() on the same thread;
//  - cross_thread: a receiver thread blocked in a WaitSet on the subscriber's HAS_DATA
//    state takes it.
// iceoryx headers stay in this file.

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench/ipc/cpu_pinning.hpp"
#include "bench/ipc/ipc_bench.hpp"
#include "bench/ipc/latency_samples.hpp"
#include "executors/clock.hpp"
#include "iceoryx_hoofs/log/logmanager.hpp"
#include "iceoryx_hoofs/platform/platform_settings.hpp"
#include "iceoryx_hoofs/posix_wrapper/posix_access_rights.hpp"
#include "iceoryx_posh/iceoryx_posh_config.hpp"
#include "iceoryx_posh/iceoryx_posh_types.hpp"
#include "iceoryx_posh/internal/roudi/roudi.hpp"
#include "iceoryx_posh/mepoo/mepoo_config.hpp"
#include "iceoryx_posh/mepoo/segment_config.hpp"
#include "iceoryx_posh/popo/untyped_publisher.hpp"
#include "iceoryx_posh/popo/untyped_subscriber.hpp"
#include "iceoryx_posh/popo/wait_set.hpp"
#include "iceoryx_posh/roudi/iceoryx_roudi_components.hpp"
#include "iceoryx_posh/runtime/posh_runtime_single_process.hpp"

namespace scancrew::bench {

namespace {

// Head of every chunk's user payload; payload_bytes (never written in the loop) follow.
struct Stamp {
  int64_t t0_ns;  // monotonic time just before loan()
  uint64_t seq;
};

// Chunks in flight per case at most: the subscriber's queue, one taken, one loaned.
constexpr uint64_t kQueueCapacity = 4;
constexpr uint32_t kChunksPerPool = 8;
// A pool's chunk payload beyond the benchmark payload: the stamp, rounded up with slack.
constexpr uint32_t kChunkMargin = 64;

// One mempool per payload size (chunks of payload + kChunkMargin user payload; RouDi adds
// the chunk header), kChunksPerPool chunks each: 178 MB of shared memory for the default
// payloads (8 x 16 MB dominates), in one segment readable and writable by this process's
// group.
iox::RouDiConfig_t roudi_config(const IpcOptions& options) {
  std::vector<size_t> sizes = options.payload_bytes;
  std::sort(sizes.begin(), sizes.end());
  sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
  iox::mepoo::MePooConfig mempools;
  for (size_t payload : sizes) {
    const auto chunk = static_cast<uint32_t>((payload + kChunkMargin + 7) / 8 * 8);
    mempools.addMemPool({chunk, kChunksPerPool});
  }
  iox::RouDiConfig_t config;
  config.setDefaults();  // RouDi's own settings; the default segment is replaced below
  config.m_sharedMemorySegments.clear();
  const auto group = iox::posix::PosixGroup::getGroupOfCurrentProcess().getName();
  config.m_sharedMemorySegments.push_back({group, group, mempools});
  return config;
}

// True when another RouDi (a daemon or another bench) holds iceoryx's lock file: creating
// a second one would end this process (iceoryx treats it as a fatal error).
bool other_roudi_running() {
  const std::string path =
      std::string(iox::platform::IOX_LOCK_FILE_PATH_PREFIX) + iox::roudi::ROUDI_LOCK_NAME + ".lock";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;  // no lock file: nobody holds it
  const bool held = ::flock(fd, LOCK_EX | LOCK_NB) != 0;
  if (!held) (void)::flock(fd, LOCK_UN);
  ::close(fd);
  return held;
}

// Sends this process's stdout to stderr while alive: RouDi announces itself on std::cout
// (not through its logger), which would break `--json`'s one object on stdout. Only for
// RouDi's start-up, while nothing else of the bench writes to stdout.
class StdoutToStderr {
 public:
  StdoutToStderr() {
    std::cout.flush();
    std::fflush(stdout);
    saved_ = ::dup(STDOUT_FILENO);
    if (saved_ >= 0) (void)::dup2(STDERR_FILENO, STDOUT_FILENO);
  }
  ~StdoutToStderr() {
    std::cout.flush();
    std::fflush(stdout);
    if (saved_ < 0) return;
    (void)::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
  }
  StdoutToStderr(const StdoutToStderr&) = delete;
  StdoutToStderr& operator=(const StdoutToStderr&) = delete;

 private:
  int saved_ = -1;
};

// Waits up to 5 s for the match: RouDi connects the ports in its discovery loop (every
// 100 ms). True when the publisher has its subscriber.
bool wait_for_match(const iox::popo::UntypedPublisher& publisher,
                    const iox::popo::UntypedSubscriber& subscriber) {
  const int64_t match_deadline = monotonic_now_ns() + 5'000'000'000;
  while (monotonic_now_ns() < match_deadline &&
         !(publisher.hasSubscribers() &&
           subscriber.getSubscriptionState() == iox::SubscribeState::SUBSCRIBED))
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return publisher.hasSubscribers();
}

// Takes everything queued, recording latency when take() returns; releases each chunk.
void take_all(iox::popo::UntypedSubscriber& subscriber, DeliveryState& state) {
  size_t n = 0;
  for (;;) {
    auto taken = subscriber.take();
    if (taken.has_error()) break;
    const int64_t now = monotonic_now_ns();
    const void* chunk = taken.value();
    if (state.measuring.load(std::memory_order_relaxed))
      state.samples.add(now - static_cast<const Stamp*>(chunk)->t0_ns);
    subscriber.release(chunk);
    ++n;
  }
  if (n) state.received.fetch_add(n, std::memory_order_release);
}

// cross_thread's receiver: a thread pinned to CPU 1, blocked in `waitset` (the subscriber's
// HAS_DATA attached) until the subscriber has data; the WaitSet times out every 100 ms to see
// `stop`.
std::thread start_receiver(iox::popo::UntypedSubscriber& subscriber, iox::popo::WaitSet<>& waitset,
                           DeliveryState& state) {
  return std::thread([&subscriber, &waitset, &state] {
    pin_to_cpu(1);
    while (!state.stop.load()) {
      (void)waitset.timedWait(iox::units::Duration::fromMilliseconds(100));
      take_all(subscriber, state);
    }
  });
}

// The measured loop: loans, stamps and publishes warm-up + options.samples chunks of
// payload bytes after the stamp, waiting for each (await_delivery); counts in result.lost the
// ones not loaned or not delivered.
void publish_samples(iox::popo::UntypedPublisher& publisher,
                     iox::popo::UntypedSubscriber& subscriber, bool cross_thread,
                     const IpcOptions& options, DeliveryState& state, IpcResult& result) {
  const auto take = [&] { take_all(subscriber, state); };
  const int warmup = 500;  // unrecorded: the receiving thread and core settle
  const auto chunk_bytes = static_cast<uint32_t>(sizeof(Stamp) + result.payload_bytes);
  for (int i = 0; i < warmup + options.samples; ++i) {
    state.measuring.store(i >= warmup, std::memory_order_relaxed);
    const uint64_t before = state.received.load(std::memory_order_acquire);
    const int64_t t0 = monotonic_now_ns();
    auto loan = publisher.loan(chunk_bytes, alignof(Stamp));
    if (loan.has_error()) {
      ++result.lost;
      continue;
    }
    auto* stamp = static_cast<Stamp*>(loan.value());
    stamp->t0_ns = t0;
    stamp->seq = static_cast<uint64_t>(i);
    publisher.publish(loan.value());
    if (!await_delivery(state.received, before, cross_thread, options.gap_us, take)) ++result.lost;
  }
}

IpcResult run_case(size_t payload, bool cross_thread, const IpcOptions& options) {
  IpcResult result{"iceoryx", cross_thread ? "cross_thread" : "same_thread", payload};
  // a service per case: the previous case's ports may still be waiting for RouDi's clean-up
  const std::string event = "blob_" + std::to_string(payload) + (cross_thread ? "_cross" : "_same");
  const iox::capro::ServiceDescription service(
      "scancrew", "bench", iox::capro::IdString_t(iox::cxx::TruncateToCapacity, event));
  iox::popo::PublisherOptions publisher_options;
  publisher_options.historyCapacity = 0;
  iox::popo::UntypedPublisher publisher(service, publisher_options);
  iox::popo::SubscriberOptions subscriber_options;
  subscriber_options.queueCapacity = kQueueCapacity;
  iox::popo::UntypedSubscriber subscriber(service, subscriber_options);
  if (!wait_for_match(publisher, subscriber)) {
    std::fprintf(stderr, "bench ipc: iceoryx %s: publisher and subscriber never matched\n",
                 event.c_str());
    result.lost = static_cast<size_t>(options.samples);
    return result;
  }

  DeliveryState state(static_cast<size_t>(options.samples));
  std::optional<iox::popo::WaitSet<>> waitset;
  std::thread receiver;
  if (cross_thread) {
    waitset.emplace();
    if (waitset->attachState(subscriber, iox::popo::SubscriberState::HAS_DATA).has_error()) {
      std::fprintf(stderr, "bench ipc: iceoryx %s: cannot attach the subscriber to a WaitSet\n",
                   event.c_str());
      result.lost = static_cast<size_t>(options.samples);
      return result;
    }
    pin_to_cpu(0);
    receiver = start_receiver(subscriber, *waitset, state);
  }
  publish_samples(publisher, subscriber, cross_thread, options, state, result);
  state.stop.store(true);
  if (receiver.joinable()) {
    receiver.join();
    unpin();
    waitset->detachState(subscriber, iox::popo::SubscriberState::HAS_DATA);
  }
  subscriber.releaseQueuedData();
  state.samples.summarise(result);
  return result;
}

}  // namespace

std::vector<IpcResult> bench_iceoryx(const IpcOptions& options) {
  // errors only (to stderr), set before anything of iceoryx logs: its loggers take the
  // default level when first used. Left out: warnings such as "RouDi not found - waiting",
  // written when the runtime registers before RouDi's thread listens (it then retries).
  iox::log::LogManager::GetLogManager().SetDefaultLogLevel(iox::log::LogLevel::kError,
                                                           iox::log::LogLevelOutput::kHideLogLevel);
  std::vector<IpcResult> out;
  if (other_roudi_running()) {
    std::fprintf(stderr, "bench ipc: iceoryx skipped: another RouDi holds /tmp/%s.lock\n",
                 iox::roudi::ROUDI_LOCK_NAME);
    for (bool cross : {false, true})
      for (size_t payload : options.payload_bytes) {
        IpcResult skipped{"iceoryx", cross ? "cross_thread" : "same_thread", payload};
        skipped.lost = static_cast<size_t>(options.samples);
        out.push_back(skipped);
      }
    return out;
  }
  // RouDi in this process, then this process's runtime; destroyed in reverse order after
  // the cases' ports. RouDi must not kill "its" processes on exit: this one is the only one.
  // RouDi's "ready" line is printed by its message thread before it answers the runtime's
  // registration, so it has been written once the runtime exists.
  std::optional<StdoutToStderr> startup(std::in_place);
  const iox::RouDiConfig_t config = roudi_config(options);
  iox::roudi::IceOryxRouDiComponents components(config);
  iox::roudi::RouDi roudi(
      components.rouDiMemoryManager, components.portManager,
      iox::roudi::RouDi::RoudiStartupParameters{iox::roudi::MonitoringMode::OFF,
                                                /*killProcessesInDestructor=*/false});
  iox::runtime::PoshRuntimeSingleProcess runtime("scancrew_bench_ipc");
  startup.reset();
  for (bool cross : {false, true})
    for (size_t payload : options.payload_bytes) out.push_back(run_case(payload, cross, options));
  return out;
}

}  // namespace scancrew::bench
