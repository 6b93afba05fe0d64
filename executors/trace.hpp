#pragma once

// Tracer: the compute time of every callback the executors run, per component, and a
// timeline of them in Chrome trace event format (trace.json; opens in Perfetto).
// Thesis: the run outputs of the evaluation (per-component latency); docs/runtime.md,
// "Tracing".
//
// An executor given a Tracer (Executor::set_tracer, StepExecutor::set_tracer) times each
// execute() that ran a callback (subscription or timer) on the monotonic clock and records
//  - always-cheap totals per component: callbacks, total time, a log-linear histogram of
//    durations (p50/p99 within 12.5 %; LatencyHistogram);
//  - a complete event {source, thread, start, duration} into a buffer of max_events
//    entries allocated up front; when it is full, further events are only counted
//    (dropped_events), the totals still grow.
// An executor without a tracer pays one predicted branch per callback; with a disabled
// tracer, two. Nothing is allocated on the callback path.
//
// Thread safety: attach() at set-up, while no executor using this tracer runs (it
// allocates). execute() from any number of executor threads (an atomic index into the
// preallocated buffer; per-component atomics). component_times() at any time (a racy but
// monotone snapshot); events(), event_count() and write_chrome_trace() once the executors
// that record into it have stopped (their threads joined).
// An executable reports to one tracer: the last one that attached it.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "executors/executable.hpp"
#include "executors/latency_histogram.hpp"

namespace scancrew {

// One callback run, as the buffer holds it.
struct TraceEvent {
  int64_t start_ns = 0;  // monotonic, since the tracer was created
  int64_t duration_ns = 0;
  uint32_t source = 0;  // Tracer::source_component()/source_what() name it
  uint32_t thread = 0;  // small per-process thread number, from 1
};

// The compute time of one component's callbacks.
struct ComponentTime {
  std::string component;  // "r1/tsdf_mapper"
  uint64_t callbacks = 0;
  double total_ms = 0;
  double p50_ms = 0, p99_ms = 0;  // per callback
};

class Tracer {
 public:
  // Allocates the event buffer (max_events × 24 bytes; pages are touched only as events
  // arrive). max_events = 0 keeps the totals only. Starts enabled.
  explicit Tracer(size_t max_events);
  ~Tracer();
  Tracer(const Tracer&) = delete;
  Tracer& operator=(const Tracer&) = delete;

  // Names the executable's callbacks by its component and topic/timer (set-up; allocates).
  void attach(Executable& executable);

  // Runs executable.execute(); when it ran a callback and the tracer is enabled, records it.
  // Returns what execute() returned. Allocation-free.
  bool execute(Executable& executable);

  // A disabled tracer records nothing (its totals stay as they are).
  void set_enabled(bool enabled) { enabled_.store(enabled, std::memory_order_relaxed); }
  bool enabled() const { return enabled_.load(std::memory_order_relaxed); }

  size_t capacity() const { return capacity_; }
  size_t event_count() const;
  uint64_t dropped_events() const { return dropped_.load(std::memory_order_relaxed); }
  std::span<const TraceEvent> events() const { return {events_.get(), event_count()}; }
  const std::string& source_component(uint32_t source) const;
  const std::string& source_what(uint32_t source) const;

  // Per component (attached ones, also those that never ran), by total_ms descending.
  std::vector<ComponentTime> component_times() const;

  // Streams {"traceEvents":[...], "displayTimeUnit":"ms", "otherData":{...}} to path:
  // one "X" event per recorded callback (name: component, cat: topic or timer, ts/dur in
  // µs, pid: the robot namespace, tid: the thread) and "M" events naming the processes
  // (the namespace, "team" for shared components) and threads. Fails naming the path.
  Result<void, std::string> write_chrome_trace(const std::string& path) const;

 private:
  struct ComponentStats;
  struct Source {
    uint32_t component = 0;  // index into components_
    std::string what;
  };
  uint32_t component_index(const std::string& name);
  void record(uint32_t source, int64_t start_ns, int64_t end_ns);

  const size_t capacity_;
  const int64_t origin_ns_;
  std::unique_ptr<TraceEvent[]> events_;
  std::atomic<size_t> next_{0};
  std::atomic<uint64_t> dropped_{0};
  std::atomic<bool> enabled_{true};
  std::vector<Source> sources_;
  std::vector<std::unique_ptr<ComponentStats>> components_;
};

}  // namespace scancrew
