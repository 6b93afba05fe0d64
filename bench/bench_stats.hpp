#pragma once

// Small figures every benchmark prints: elapsed milliseconds, mean, percentile, maximum,
// and the machine's load (other processes skew timings, so benches record it).

#include <stdlib.h>  // getloadavg

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <vector>

namespace scancrew::bench {

using Clock = std::chrono::steady_clock;

inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

inline double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / static_cast<double>(v.size());
}

// The value at rank p·(n − 1) (p in [0, 1]), no interpolation.
inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  const auto k = static_cast<size_t>(p * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

inline double max_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

// The machine's 1-minute load average; −1 when unavailable.
inline double load_average() {
  double load[1] = {0};
  return ::getloadavg(load, 1) == 1 ? load[0] : -1.0;
}

}  // namespace scancrew::bench
