#pragma once

// Contract checks. A broken contract is a bug, not an input error: it prints where and
// why, then aborts. Input errors are values (see result.hpp), never checks.

#include <cstdio>
#include <cstdlib>

namespace scancrew::detail {
[[noreturn]] inline void check_failed(const char* expr, const char* msg, const char* file,
                                      int line) {
  std::fprintf(stderr, "scancrew: contract violated at %s:%d: %s (%s)\n", file, line, msg, expr);
  std::abort();
}
}  // namespace scancrew::detail

#define SCANCREW_CHECK(cond, msg)                                                  \
  do {                                                                             \
    if (!(cond)) ::scancrew::detail::check_failed(#cond, msg, __FILE__, __LINE__); \
  } while (false)
