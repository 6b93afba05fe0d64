#include "executors/step_executor.hpp"

#include <algorithm>

#include "executors/check.hpp"

namespace scancrew {

StepExecutor::~StepExecutor() {
  for (Executable* e : executables_) e->set_wake_target(nullptr);
}

void StepExecutor::add(Executable& executable) {
  SCANCREW_CHECK(executable.wall_deadline_ns() == Executable::kNoDeadline,
                 "a StepExecutor runs on sim time only: create timers on the sim clock");
  executables_.push_back(&executable);
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
  std::erase(executables_, &executable);
}

size_t StepExecutor::drain(size_t max_units) {
  size_t ran = 0;
  bool progress = true;
  while (progress) {
    progress = false;
    for (Executable* e : executables_) {
      if (!e->enabled() || !e->has_work()) continue;
      if (tracer_ == nullptr ? e->execute() : tracer_->execute(*e)) {
        ++ran;
        progress = true;
        SCANCREW_CHECK(ran < max_units, "StepExecutor: callbacks keep producing work (livelock?)");
      }
    }
  }
  return ran;
}

size_t StepExecutor::run_until(int64_t t_ns, size_t max_units) {
  SCANCREW_CHECK(t_ns >= clock_.now_ns(), "run_until: sim time must not go backward");
  size_t ran = drain(max_units);
  while (true) {
    int64_t next = Executable::kNoDeadline;
    for (Executable* e : executables_)
      if (e->enabled()) next = std::min(next, e->sim_deadline_ns());
    if (next > t_ns) break;
    if (next > clock_.now_ns()) clock_.advance_to(next);
    ran += drain(max_units - ran);
  }
  if (t_ns > clock_.now_ns()) clock_.advance_to(t_ns);
  ran += drain(max_units - ran);
  return ran;
}

}  // namespace scancrew
