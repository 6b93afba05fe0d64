#pragma once

// Pins the calling thread to one CPU, so a cross-thread case measures a hand-over between
// two cores instead of the scheduler's time slice (on 2 cores, a publisher that waits for
// the acknowledgement on the receiver's core delays it by a whole slice). No-op with one
// CPU or when the kernel refuses.

#include <pthread.h>
#include <sched.h>

#include <thread>

namespace scancrew::bench {

inline void pin_to_cpu(unsigned cpu) {
  if (std::thread::hardware_concurrency() < 2) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu % std::thread::hardware_concurrency(), &set);
  (void)pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
}

// Undoes pin_to_cpu for the calling thread.
inline void unpin() {
  cpu_set_t set;
  CPU_ZERO(&set);
  for (unsigned i = 0; i < std::thread::hardware_concurrency(); ++i) CPU_SET(i, &set);
  (void)pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
}

}  // namespace scancrew::bench
