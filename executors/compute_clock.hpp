#pragma once

// ComputeClock: the CPU time a callback spends, for charging it on its place's timeline
// (StepExecutor, compute_time: charged; docs/runtime.md, "Compute-charged time").
//
// A callback's compute is the CPU time of the thread that runs it
// (CLOCK_THREAD_CPUTIME_ID), plus that of the TBB worker threads, which run the parallel
// loops it starts (the TSDF integrator, the ISE pipeline). CPU time, not wall time: another
// process on the machine takes cores away but barely changes the CPU time a piece of work
// needs, so a charged run does not depend on how loaded this machine is.
//
// TBB workers are found by a task_scheduler_observer that registers every worker thread of
// the default arena as it joins (observe_tbb_workers(), idempotent). A worker that spins
// idle after a parallel loop is charged to whatever callback runs then: at most the TBB
// spin time (about a millisecond) per loop.
//
// Thread safety: sample() may be called from any thread; observe_tbb_workers() once or
// more, from any thread.

#include <cstdint>

namespace scancrew {

struct CpuSample {
  int64_t thread_ns = 0;   // the calling thread
  int64_t workers_ns = 0;  // every TBB worker thread registered so far, summed
};

class ComputeClock {
 public:
  // Starts watching TBB's worker threads (the first call; later calls do nothing).
  static void observe_tbb_workers();
  // The CPU time used so far by the calling thread and by the TBB workers.
  static CpuSample sample();
  // The CPU time of the calling thread only.
  static int64_t thread_cpu_ns();
};

// What a callback that used `thread_ns` on its own thread and `workers_ns` on helper
// threads costs on a place with `cores` cores of a computer `scale` times slower than this
// one: the work spread over the cores, but never less than its own thread's share (which
// holds its serial part):  scale · max(thread, (thread + workers) / cores).
int64_t charged_ns(int64_t thread_ns, int64_t workers_ns, int cores, double scale);

}  // namespace scancrew
