#pragma once

// Exact latency samples of one benchmark case, preallocated (recording allocates nothing).

#include <cstdint>
#include <vector>

#include "bench/ipc/ipc_bench.hpp"

namespace scancrew::bench {

class LatencySamples {
 public:
  explicit LatencySamples(size_t capacity) { values_ns_.reserve(capacity); }
  void add(int64_t ns) {
    if (values_ns_.size() < values_ns_.capacity()) values_ns_.push_back(ns);
  }
  size_t size() const { return values_ns_.size(); }
  void clear() { values_ns_.clear(); }
  // Sorts and fills p50/p99/max (µs) of `result`.
  void summarise(IpcResult& result);

 private:
  std::vector<int64_t> values_ns_;
};

}  // namespace scancrew::bench
