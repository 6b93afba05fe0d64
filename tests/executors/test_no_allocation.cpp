// Steady-state publish and delivery allocate nothing on the heap. This binary replaces
// the global operator new to count allocations while a window is open, on any thread.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <thread>

#include "executors/executor.hpp"
#include "executors/publisher.hpp"
#include "executors/subscription.hpp"
#include "executors/timer.hpp"
#include "executors/trace.hpp"
#include "tests/executors/test_messages.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<size_t> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed))
    g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace scancrew {
namespace {

using test::Blob;

struct AllocationWindow {
  AllocationWindow() {
    g_allocations.store(0);
    g_counting.store(true);
  }
  size_t close() {
    g_counting.store(false);
    return g_allocations.load();
  }
};

// One loan -> fill -> publish -> callback round of a variable-size payload.
bool publish_one(Publisher<Blob>& pub, size_t bytes, uint8_t fill) {
  auto loan = pub.loan();
  if (!loan) return false;
  (*loan)->bytes.resize(bytes);  // capacity kept from earlier rounds: no allocation
  (*loan)->bytes[0] = fill;
  return pub.publish(std::move(*loan)).has_value();
}

// Gives every slot of the pool the capacity of `bytes` (the warm-up of a recycled pool).
void warm_every_slot(Publisher<Blob>& pub, size_t bytes) {
  std::vector<Loan<Blob>> all;
  while (auto loan = pub.loan()) {
    (*loan)->bytes.resize(bytes);
    all.push_back(std::move(loan).value());
  }
}

TEST(NoAllocation, SteadyStatePublishAndDeliveryOnOneThreadAllocateNothing) {
  WallClock clock;
  CallbackGroup group("g", CallbackGroup::Type::kMutuallyExclusive);
  auto topic = std::make_shared<Topic<Blob>>("/blob", 4);
  Publisher<Blob> pub(topic, 0, &clock, nullptr);
  uint64_t sum = 0;
  Subscription<Blob> a(
      topic, {.depth = 2}, [&](Sample<Blob>&& s) { sum += s->bytes[0]; }, group, nullptr);
  Subscription<Blob> b(
      topic, {.depth = 1}, [&](Sample<Blob>&& s) { sum += s->bytes.size(); }, group, nullptr);
  SingleThreadedExecutor executor;
  executor.add(a);
  executor.add(b);
  warm_every_slot(pub, 1 << 20);
  ASSERT_EQ(topic->pool().available(), 4u);
  AllocationWindow window;
  for (int i = 0; i < 1000; ++i) {
    ASSERT_TRUE(publish_one(pub, (i % 2 ? 1 << 20 : 1000), static_cast<uint8_t>(i)));
    if (i % 3 == 0) {
      ASSERT_TRUE(publish_one(pub, 512, 1));  // overflows b: a keep-last drop
    }
    executor.spin_some();
  }
  EXPECT_EQ(window.close(), 0u);
  EXPECT_GT(sum, 0u);
  EXPECT_GT(b.queue().dropped.load(), 0u);
  executor.remove(a);
  executor.remove(b);
}

TEST(NoAllocation, TracedCallbacksAllocateNothingAlsoWhenTheBufferIsFull) {
  WallClock clock;
  CallbackGroup group("g", CallbackGroup::Type::kMutuallyExclusive);
  auto topic = std::make_shared<Topic<Blob>>("/blob", 4);
  Publisher<Blob> pub(topic, 0, &clock, nullptr);
  uint64_t sum = 0;
  Subscription<Blob> sub(
      topic, {.depth = 2}, [&](Sample<Blob>&& s) { sum += s->bytes[0]; }, group, nullptr);
  Timer timer(
      clock, 1, [&] { ++sum; }, group, nullptr);  // due at every look
  Tracer tracer(500);  // fills up half-way: both the recording and the dropping path run
  SingleThreadedExecutor executor;
  executor.set_tracer(&tracer);
  executor.add(sub);
  executor.add(timer);
  warm_every_slot(pub, 1000);
  AllocationWindow window;
  for (int i = 0; i < 1000; ++i) {
    ASSERT_TRUE(publish_one(pub, 1000, 1));
    executor.spin_some(2);
  }
  EXPECT_EQ(window.close(), 0u);
  EXPECT_EQ(tracer.event_count(), 500u);
  EXPECT_GT(tracer.dropped_events(), 0u);
  uint64_t callbacks = 0;
  for (const auto& t : tracer.component_times()) callbacks += t.callbacks;
  EXPECT_EQ(callbacks, executor.executed());
  EXPECT_EQ(callbacks, tracer.event_count() + tracer.dropped_events());
  executor.remove(sub);
  executor.remove(timer);
}

TEST(NoAllocation, SteadyStateDeliveryToAnotherThreadAllocatesNothing) {
  WallClock clock;
  CallbackGroup group("g", CallbackGroup::Type::kMutuallyExclusive);
  auto topic = std::make_shared<Topic<Blob>>("/blob", 4);
  Publisher<Blob> pub(topic, 0, &clock, nullptr);
  std::atomic<uint64_t> received{0};
  Subscription<Blob> sub(
      topic, {.depth = 4},
      [&](Sample<Blob>&&) { received.fetch_add(1, std::memory_order_release); }, group, nullptr);
  MultiThreadedExecutor executor(2);
  executor.add(sub);
  std::thread spinner([&] { executor.spin(); });
  const auto wait_for = [&](uint64_t n) {
    const int64_t give_up = monotonic_now_ns() + 5'000'000'000;
    while (received.load(std::memory_order_acquire) < n && monotonic_now_ns() < give_up)
      std::this_thread::yield();
    return received.load() >= n;
  };
  // however the threads interleave, any slot may be in use: warm them all
  warm_every_slot(pub, 4096);
  for (int i = 0; i < 16; ++i) {
    ASSERT_TRUE(publish_one(pub, 4096, 1));
    ASSERT_TRUE(wait_for(static_cast<uint64_t>(i) + 1));
  }
  AllocationWindow window;
  for (uint64_t i = 0; i < 500; ++i) {
    if (!publish_one(pub, 4096, 2)) break;
    if (!wait_for(17 + i)) break;
  }
  const size_t allocations = window.close();
  executor.stop();
  spinner.join();
  executor.remove(sub);
  EXPECT_EQ(received.load(), 516u);
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace scancrew
