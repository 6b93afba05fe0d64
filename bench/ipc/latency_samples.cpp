#include "bench/ipc/latency_samples.hpp"

#include <algorithm>

namespace scancrew::bench {

void LatencySamples::summarise(IpcResult& result) {
  if (values_ns_.empty()) return;
  std::sort(values_ns_.begin(), values_ns_.end());
  const auto at = [&](double q) {
    return static_cast<double>(
               values_ns_[static_cast<size_t>(q * static_cast<double>(values_ns_.size() - 1))]) *
           1e-3;
  };
  result.p50_us = at(0.5);
  result.p99_us = at(0.99);
  result.max_us = static_cast<double>(values_ns_.back()) * 1e-3;
}

}  // namespace scancrew::bench
