#include "executors/executor.hpp"

#include <algorithm>
#include <chrono>

#include "core/check.hpp"

namespace scancrew {

Executor::Executor(size_t num_threads, int64_t spin_ns)
    : num_threads_(num_threads), spin_ns_(spin_ns) {
  SCANCREW_CHECK(num_threads >= 1, "an executor needs at least one thread");
  SCANCREW_CHECK(spin_ns >= 0, "spin time must not be negative");
}

Executor::~Executor() {
  std::lock_guard lock(mutex_);
  for (Executable* e : executables_) e->set_wake_target(nullptr);
}

void Executor::add(Executable& executable) {
  {
    std::lock_guard lock(mutex_);
    SCANCREW_CHECK(
        std::find(executables_.begin(), executables_.end(), &executable) == executables_.end(),
        "executable added twice");
    executables_.push_back(&executable);
    if (tracer_ != nullptr) tracer_->attach(executable);
  }
  executable.set_wake_target(this);
  wake();
}

void Executor::remove(Executable& executable) {
  executable.set_wake_target(nullptr);
  std::lock_guard lock(mutex_);
  std::erase(executables_, &executable);
  rr_ = 0;
}

void Executor::wake() {
  epoch_.fetch_add(1, std::memory_order_seq_cst);
  if (sleepers_.load(std::memory_order_seq_cst) > 0) {
    std::lock_guard lock(mutex_);
    cv_.notify_all();
  }
}

void Executor::stop() {
  stop_.store(true, std::memory_order_seq_cst);
  std::lock_guard lock(mutex_);
  cv_.notify_all();
}

Executable* Executor::claim_ready_locked() {
  const size_t n = executables_.size();
  for (size_t k = 0; k < n; ++k) {
    Executable* e = executables_[(rr_ + k) % n];
    if (!e->enabled() || !e->has_work()) continue;
    if (!e->group().try_enter()) {
      group_contended_.store(true, std::memory_order_relaxed);
      continue;
    }
    rr_ = (rr_ + k + 1) % n;
    return e;
  }
  return nullptr;
}

void Executor::set_tracer(Tracer* tracer) {
  std::lock_guard lock(mutex_);
  tracer_ = tracer;
  if (tracer_ != nullptr)
    for (Executable* e : executables_) tracer_->attach(*e);
}

void Executor::run(Executable* executable) {
  const bool ran = tracer_ == nullptr ? executable->execute() : tracer_->execute(*executable);
  if (ran) executed_.fetch_add(1, std::memory_order_relaxed);
  executable->group().leave();
  // a thread that found this group busy skipped its work: let it look again
  if (group_contended_.exchange(false, std::memory_order_relaxed)) wake();
}

void Executor::wait_for_work_locked(std::unique_lock<std::mutex>& lock, uint64_t seen_epoch,
                                    int64_t until_ns) {
  int64_t deadline = until_ns;
  for (Executable* e : executables_)
    if (e->enabled()) deadline = std::min(deadline, e->wall_deadline_ns());
  sleepers_.fetch_add(1, std::memory_order_seq_cst);
  const auto woken = [&] {
    return stop_.load(std::memory_order_relaxed) ||
           epoch_.load(std::memory_order_seq_cst) != seen_epoch;
  };
  if (deadline == Executable::kNoDeadline) {
    cv_.wait(lock, woken);
  } else {
    const auto tp = std::chrono::steady_clock::time_point(std::chrono::nanoseconds(deadline));
    cv_.wait_until(lock, tp, woken);
  }
  sleepers_.fetch_sub(1, std::memory_order_seq_cst);
}

bool Executor::spin_for_work(uint64_t seen_epoch) const {
  if (spin_ns_ == 0) return false;
  const int64_t until = monotonic_now_ns() + spin_ns_;
  do {
    if (epoch_.load(std::memory_order_acquire) != seen_epoch) return true;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  } while (monotonic_now_ns() < until && !stop_.load(std::memory_order_relaxed));
  return false;
}

void Executor::worker_loop() {
  while (!stop_.load(std::memory_order_acquire)) {
    const uint64_t seen = epoch_.load(std::memory_order_seq_cst);
    std::unique_lock lock(mutex_);
    if (Executable* e = claim_ready_locked()) {
      lock.unlock();
      run(e);
      continue;
    }
    lock.unlock();
    if (spin_for_work(seen)) continue;
    lock.lock();
    wait_for_work_locked(lock, seen, Executable::kNoDeadline);
  }
}

void Executor::spin() {
  std::vector<std::thread> workers;
  workers.reserve(num_threads_ - 1);
  for (size_t i = 1; i < num_threads_; ++i) workers.emplace_back([this] { worker_loop(); });
  worker_loop();
  for (auto& t : workers) t.join();
  stop_.store(false);  // a later spin() runs again
}

bool Executor::spin_once(int64_t timeout_ns) {
  const int64_t until = monotonic_now_ns() + timeout_ns;
  while (true) {
    const uint64_t seen = epoch_.load(std::memory_order_seq_cst);
    std::unique_lock lock(mutex_);
    if (Executable* e = claim_ready_locked()) {
      lock.unlock();
      run(e);
      return true;
    }
    if (monotonic_now_ns() >= until || stop_.load()) return false;
    wait_for_work_locked(lock, seen, until);
  }
}

size_t Executor::spin_some(size_t max_units) {
  size_t ran = 0;
  while (ran < max_units) {
    std::unique_lock lock(mutex_);
    Executable* e = claim_ready_locked();
    if (e == nullptr) break;
    lock.unlock();
    run(e);
    ++ran;
  }
  return ran;
}

}  // namespace scancrew
