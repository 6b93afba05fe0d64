#include "tests/core/tsga/allocation_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<bool> g_tracking{false};
std::atomic<size_t> g_allocations{0};
}  // namespace

void* operator new(size_t n) {
  if (g_tracking.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, size_t /*n*/) noexcept {
  std::free(p);
}

namespace scancrew::tsga::test {

void start_counting_allocations() {
  g_allocations = 0;
  g_tracking = true;
}

size_t stop_counting_allocations() {
  g_tracking = false;
  return g_allocations.load();
}

}  // namespace scancrew::tsga::test
