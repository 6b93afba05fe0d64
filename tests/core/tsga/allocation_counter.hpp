#pragma once

// Counts global operator new calls between start() and stop(). The replaced operators live
// in allocation_counter.cpp, away from GoogleTest's code, so that g++ does not inline them
// into it (where it reports new/free pairs as mismatched).

#include <cstddef>

namespace scancrew::tsga::test {

void start_counting_allocations();
// the allocations since start_counting_allocations(); counting stops
size_t stop_counting_allocations();

}  // namespace scancrew::tsga::test
