#include "executors/step_executor.hpp"

#include <algorithm>

#include "core/check.hpp"
#include "executors/compute_clock.hpp"

namespace scancrew {

namespace {

// std::push_heap keeps the largest first: "later" orders after.
bool later(const auto& a, const auto& b) {
  return a.due_ns != b.due_ns ? a.due_ns > b.due_ns : a.order > b.order;
}

}  // namespace

std::string_view to_string(ComputeTime mode) {
  return name_of(kComputeTimeNames, mode);
}

StepExecutor::~StepExecutor() {
  discard_pending();
  for (Executable* e : executables_) e->set_wake_target(nullptr);
}

void StepExecutor::set_compute_time(ComputeTime mode, ComputeCharge charge) {
  SCANCREW_CHECK(charge.cores >= 1 && charge.scale > 0, "compute charge: cores >= 1, scale > 0");
  mode_ = mode;
  charge_ = charge;
  if (mode_ == ComputeTime::kCharged) ComputeClock::observe_tbb_workers();
}

int StepExecutor::add_place(std::string name) {
  places_.push_back(Place{.name = std::move(name)});
  return static_cast<int>(places_.size()) - 1;
}

void StepExecutor::add(Executable& executable, int place) {
  SCANCREW_CHECK(executable.wall_deadline_ns() == Executable::kNoDeadline,
                 "a StepExecutor runs on sim time only: create timers on the sim clock");
  SCANCREW_CHECK(place == kWorld || (place >= 0 && place < static_cast<int>(places_.size())),
                 "StepExecutor::add: no such place");
  executables_.push_back(&executable);
  place_of_.push_back(place);
  if (place != kWorld) places_[static_cast<size_t>(place)].members.push_back(&executable);
  if (tracer_ != nullptr) tracer_->attach(executable);
  executable.set_wake_target(this);
}

void StepExecutor::set_tracer(Tracer* tracer) {
  tracer_ = tracer;
  if (tracer_ != nullptr)
    for (Executable* e : executables_) tracer_->attach(*e);
}

void StepExecutor::remove(Executable& executable) {
  executable.set_wake_target(nullptr);
  for (size_t i = 0; i < executables_.size(); ++i)
    if (executables_[i] == &executable) {
      executables_.erase(executables_.begin() + static_cast<std::ptrdiff_t>(i));
      place_of_.erase(place_of_.begin() + static_cast<std::ptrdiff_t>(i));
      break;
    }
  for (Place& p : places_) {
    std::erase(p.members, &executable);
    p.next = 0;
  }
}

std::vector<PlaceStats> StepExecutor::place_stats() const {
  std::vector<PlaceStats> stats;
  for (const Place& p : places_)
    stats.push_back({.name = p.name,
                     .callbacks = p.callbacks,
                     .charged_s = static_cast<double>(p.charged_ns) * 1e-9,
                     .max_callback_ms = static_cast<double>(p.max_ns) * 1e-6});
  return stats;
}

bool StepExecutor::execute(Executable& e) {
  return tracer_ == nullptr ? e.execute() : tracer_->execute(e);
}

void StepExecutor::defer(TopicBase& topic, uint32_t index) {
  deferred_.emplace_back(&topic, index);
}

bool StepExecutor::execute_charged(Executable& e, Place& place) {
  deferred_.clear();
  const CpuSample before = ComputeClock::sample();
  bool ran = false;
  {
    PublishDeferral::Scope scope(this);
    ran = execute(e);
  }
  const CpuSample after = ComputeClock::sample();
  // at least 1 ns: a place runs one callback per instant of sim time
  const int64_t cost = std::max<int64_t>(
      1, charged_ns(after.thread_ns - before.thread_ns, after.workers_ns - before.workers_ns,
                    charge_.cores, charge_.scale));
  const int64_t due = clock_.now_ns() + cost;
  for (const auto& [topic, index] : deferred_) {
    pending_.push_back({.due_ns = due, .order = delivery_order_++, .topic = topic, .index = index});
    std::push_heap(pending_.begin(), pending_.end(),
                   [](const Delivery& a, const Delivery& b) { return later(a, b); });
  }
  deferred_.clear();
  if (!ran) return false;
  place.busy_until_ns = due;
  ++place.callbacks;
  place.charged_ns += cost;
  place.max_ns = std::max(place.max_ns, cost);
  return true;
}

void StepExecutor::deliver_due() {
  const auto cmp = [](const Delivery& a, const Delivery& b) { return later(a, b); };
  while (!pending_.empty() && pending_.front().due_ns <= clock_.now_ns()) {
    std::pop_heap(pending_.begin(), pending_.end(), cmp);
    const Delivery d = pending_.back();
    pending_.pop_back();
    d.topic->deliver(d.index);
  }
}

void StepExecutor::discard_pending() {
  for (const Delivery& d : pending_) d.topic->discard(d.index);
  pending_.clear();
}

size_t StepExecutor::drain_charged(size_t max_units) {
  size_t ran = 0;
  bool progress = true;
  while (progress) {
    progress = false;
    // the world first, in registration order, as a free run
    for (size_t i = 0; i < executables_.size(); ++i) {
      if (place_of_[i] != kWorld) continue;
      Executable* e = executables_[i];
      if (!e->enabled() || !e->has_work()) continue;
      if (execute(*e)) {
        ++ran;
        progress = true;
      }
    }
    // then one callback per free place, its members taking turns
    for (Place& p : places_) {
      if (busy(p) || p.members.empty()) continue;
      const size_t n = p.members.size();
      for (size_t k = 0; k < n; ++k) {
        const size_t j = (p.next + k) % n;
        Executable* e = p.members[j];
        if (!e->enabled() || !e->has_work()) continue;
        if (execute_charged(*e, p)) {
          p.next = (j + 1) % n;
          ++ran;
          progress = true;
          break;
        }
      }
    }
    SCANCREW_CHECK(ran < max_units, "StepExecutor: callbacks keep producing work (livelock?)");
  }
  return ran;
}

size_t StepExecutor::drain(size_t max_units) {
  if (mode_ == ComputeTime::kCharged) {
    deliver_due();
    return drain_charged(max_units);
  }
  size_t ran = 0;
  bool progress = true;
  while (progress) {
    progress = false;
    for (Executable* e : executables_) {
      if (!e->enabled() || !e->has_work()) continue;
      if (execute(*e)) {
        ++ran;
        progress = true;
        SCANCREW_CHECK(ran < max_units, "StepExecutor: callbacks keep producing work (livelock?)");
      }
    }
  }
  return ran;
}

int64_t StepExecutor::next_event_ns() const {
  int64_t next = Executable::kNoDeadline;
  for (size_t i = 0; i < executables_.size(); ++i) {
    const Executable* e = executables_[i];
    if (!e->enabled()) continue;
    int64_t at = e->sim_deadline_ns();
    const int place = place_of_[i];
    if (mode_ == ComputeTime::kCharged && place != kWorld) {
      // a busy place takes its work, due or ready, when it is free again
      const Place& p = places_[static_cast<size_t>(place)];
      if (busy(p)) {
        if (at != Executable::kNoDeadline) at = std::max(at, p.busy_until_ns);
        if (e->has_work()) at = std::min(at, p.busy_until_ns);
      }
    }
    next = std::min(next, at);
  }
  if (!pending_.empty()) next = std::min(next, pending_.front().due_ns);
  return next;
}

size_t StepExecutor::run_until(int64_t t_ns, size_t max_units) {
  SCANCREW_CHECK(t_ns >= clock_.now_ns(), "run_until: sim time must not go backward");
  size_t ran = drain(max_units);
  while (true) {
    const int64_t next = next_event_ns();
    if (next > t_ns) break;
    if (next > clock_.now_ns()) clock_.advance_to(next);
    ran += drain(max_units - ran);
  }
  if (t_ns > clock_.now_ns()) clock_.advance_to(t_ns);
  ran += drain(max_units - ran);
  return ran;
}

}  // namespace scancrew
