#include "executors/compute_clock.hpp"

#include <oneapi/tbb/task_scheduler_observer.h>
#include <pthread.h>
#include <time.h>

#include <algorithm>
#include <mutex>
#include <vector>

namespace scancrew {

namespace {

int64_t cpu_ns(clockid_t clock) {
  timespec ts{};
  if (clock_gettime(clock, &ts) != 0) return 0;
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// The TBB worker threads in the arena now (their CPU time since they joined) and the CPU
// time of the stays that ended.
class WorkerRegistry final : public tbb::task_scheduler_observer {
 public:
  WorkerRegistry() { observe(true); }
  ~WorkerRegistry() override { observe(false); }

  void on_scheduler_entry(bool is_worker) override {
    if (!is_worker) return;
    clockid_t clock{};
    if (pthread_getcpuclockid(pthread_self(), &clock) != 0) return;
    std::lock_guard lock(mutex_);
    workers_.push_back({pthread_self(), clock, cpu_ns(clock)});
  }

  void on_scheduler_exit(bool is_worker) override {
    if (!is_worker) return;
    std::lock_guard lock(mutex_);
    const auto it = std::find_if(workers_.begin(), workers_.end(), [](const Worker& w) {
      return pthread_equal(w.thread, pthread_self());
    });
    if (it == workers_.end()) return;
    retired_ns_ += cpu_ns(it->clock) - it->joined_cpu_ns;
    workers_.erase(it);
  }

  int64_t total_ns() {
    std::lock_guard lock(mutex_);
    int64_t sum = retired_ns_;
    for (const Worker& w : workers_) sum += std::max<int64_t>(0, cpu_ns(w.clock) - w.joined_cpu_ns);
    return sum;
  }

 private:
  struct Worker {
    pthread_t thread;
    clockid_t clock;
    int64_t joined_cpu_ns;
  };
  std::mutex mutex_;
  std::vector<Worker> workers_;
  int64_t retired_ns_ = 0;
};

WorkerRegistry* g_registry = nullptr;
std::once_flag g_registry_once;

}  // namespace

void ComputeClock::observe_tbb_workers() {
  // never destroyed: workers may leave the arena during static destruction
  std::call_once(g_registry_once, [] { g_registry = new WorkerRegistry(); });
}

int64_t ComputeClock::thread_cpu_ns() {
  return cpu_ns(CLOCK_THREAD_CPUTIME_ID);
}

CpuSample ComputeClock::sample() {
  return {.thread_ns = thread_cpu_ns(), .workers_ns = g_registry ? g_registry->total_ns() : 0};
}

int64_t charged_ns(int64_t thread_ns, int64_t workers_ns, int cores, double scale) {
  thread_ns = std::max<int64_t>(0, thread_ns);
  workers_ns = std::max<int64_t>(0, workers_ns);
  const double spread = static_cast<double>(thread_ns + workers_ns) / std::max(1, cores);
  return static_cast<int64_t>(scale * std::max(static_cast<double>(thread_ns), spread));
}

}  // namespace scancrew
