#pragma once

// Executor: runs the callbacks of the executables added to it, event-driven.
//
// A thread with nothing to do sleeps on a condition variable until a subscription
// receives a sample (wake()), a sim clock advances, or the earliest wall-timer deadline.
// It never polls; an optional bounded spin (spin_ns) may precede the sleep. With N threads, spin()
// runs N-1 workers plus the calling thread; callback groups decide which callbacks may overlap (see
// CallbackGroup).
//
// Thread safety: add()/remove() at set-up or between spins; spin*(), stop() and wake()
// from any thread. Allocation: add()/remove() and starting threads allocate; the spin
// loop does not.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "executors/executable.hpp"
#include "executors/subscriber_queue.hpp"
#include "executors/trace.hpp"

namespace scancrew {

class Executor : public WakeTarget {
 public:
  // spin_ns: after running out of work, a spin() thread watches for new work this long
  // before it blocks (0: block at once). Trades CPU for hand-over latency: waking a
  // blocked thread on another core costs tens of µs on a VM (docs/bench_ipc.md).
  explicit Executor(size_t num_threads, int64_t spin_ns = 0);
  ~Executor() override;
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  void add(Executable& executable);
  void remove(Executable& executable);

  // Runs callbacks until stop(); blocks the caller, who is one of the threads.
  void spin();
  // On the caller's thread: runs one unit of work, waiting up to timeout_ns for one.
  // Returns whether something ran.
  bool spin_once(int64_t timeout_ns);
  // On the caller's thread: runs what is ready until nothing is (at most max_units).
  size_t spin_some(size_t max_units = SIZE_MAX);
  // Makes spin() return (in every thread) after the callbacks now running finish. A
  // stop() before spin() makes that spin() return at once.
  void stop();

  void wake() override;
  // Records every callback in tracer (null: none, the default) from now on; attaches the
  // executables added so far and later. Set-up only, while no thread spins; the tracer
  // outlives the spins.
  void set_tracer(Tracer* tracer);
  size_t num_threads() const { return num_threads_; }
  uint64_t executed() const { return executed_.load(std::memory_order_relaxed); }

 private:
  Executable* claim_ready_locked();
  void run(Executable* executable);
  void worker_loop();
  // Sleeps until woken, a wall deadline passes, timeout_ns (monotonic) or stop().
  void wait_for_work_locked(std::unique_lock<std::mutex>& lock, uint64_t seen_epoch,
                            int64_t until_ns);

  // Spins at most spin_ns_ for the epoch to move; true when it did.
  bool spin_for_work(uint64_t seen_epoch) const;

  const size_t num_threads_;
  const int64_t spin_ns_;
  std::mutex mutex_;  // guards executables_ and rr_; the mutex of cv_
  std::condition_variable cv_;
  std::vector<Executable*> executables_;
  size_t rr_ = 0;  // where the next scan starts (fairness)
  std::atomic<uint64_t> epoch_{0};
  std::atomic<int> sleepers_{0};
  std::atomic<bool> stop_{false};
  std::atomic<bool> group_contended_{false};
  std::atomic<uint64_t> executed_{0};
  Tracer* tracer_ = nullptr;
};

class SingleThreadedExecutor final : public Executor {
 public:
  explicit SingleThreadedExecutor(int64_t spin_ns = 0) : Executor(1, spin_ns) {}
};

class MultiThreadedExecutor final : public Executor {
 public:
  explicit MultiThreadedExecutor(size_t num_threads, int64_t spin_ns = 0)
      : Executor(num_threads, spin_ns) {}
};

}  // namespace scancrew
