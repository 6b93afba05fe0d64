#pragma once

// LatencyHistogram: log-linear buckets (8 per power of two, so a reported percentile is
// within 12.5% of the true value) over 0 .. 2^63 ns. Recording is one relaxed atomic add:
// safe from any thread, allocation-free. Percentiles read a racy but monotone snapshot.

#include <array>
#include <atomic>
#include <bit>
#include <cstdint>

namespace scancrew {

class LatencyHistogram {
 public:
  static constexpr int kSubBits = 3;
  static constexpr int kBuckets = 64 << kSubBits;

  void record(int64_t value_ns) {
    const uint64_t v = value_ns < 0 ? 0 : static_cast<uint64_t>(value_ns);
    buckets_[bucket_of(v)].fetch_add(1, std::memory_order_relaxed);
    count_.fetch_add(1, std::memory_order_relaxed);
    uint64_t prev = max_.load(std::memory_order_relaxed);
    while (v > prev && !max_.compare_exchange_weak(prev, v, std::memory_order_relaxed)) {
    }
  }

  uint64_t count() const { return count_.load(std::memory_order_relaxed); }
  uint64_t max_ns() const { return max_.load(std::memory_order_relaxed); }

  // The upper edge of the bucket holding the q-quantile (q in [0, 1]); 0 when empty.
  uint64_t percentile_ns(double q) const {
    const uint64_t n = count();
    if (n == 0) return 0;
    const auto rank = static_cast<uint64_t>(q * static_cast<double>(n - 1)) + 1;
    uint64_t seen = 0;
    for (int b = 0; b < kBuckets; ++b) {
      seen += buckets_[b].load(std::memory_order_relaxed);
      if (seen >= rank) return upper_edge(b) < max_ns() ? upper_edge(b) : max_ns();
    }
    return max_ns();
  }

  // Adds other's counts into this one (for per-topic aggregates).
  void merge_from(const LatencyHistogram& other) {
    for (int b = 0; b < kBuckets; ++b)
      buckets_[b].fetch_add(other.buckets_[b].load(std::memory_order_relaxed),
                            std::memory_order_relaxed);
    count_.fetch_add(other.count(), std::memory_order_relaxed);
    uint64_t prev = max_.load(std::memory_order_relaxed);
    const uint64_t v = other.max_ns();
    while (v > prev && !max_.compare_exchange_weak(prev, v, std::memory_order_relaxed)) {
    }
  }

  static int bucket_of(uint64_t v) {
    if (v < (1u << kSubBits)) return static_cast<int>(v);
    const int exponent = 63 - std::countl_zero(v);  // >= kSubBits
    const int sub = static_cast<int>((v >> (exponent - kSubBits)) & ((1u << kSubBits) - 1));
    return ((exponent - kSubBits + 1) << kSubBits) + sub;
  }

  static uint64_t upper_edge(int bucket) {
    if (bucket < (1 << kSubBits)) return static_cast<uint64_t>(bucket);
    const int exponent = (bucket >> kSubBits) + kSubBits - 1;
    const uint64_t sub = bucket & ((1 << kSubBits) - 1);
    const uint64_t base = (uint64_t{1} << exponent) + (sub << (exponent - kSubBits));
    return base + (uint64_t{1} << (exponent - kSubBits)) - 1;
  }

 private:
  std::array<std::atomic<uint64_t>, kBuckets> buckets_{};
  std::atomic<uint64_t> count_{0};
  std::atomic<uint64_t> max_{0};
};

}  // namespace scancrew
