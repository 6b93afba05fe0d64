#include <gtest/gtest.h>

#include "executors/latency_histogram.hpp"

namespace scancrew {
namespace {

TEST(LatencyHistogram, BucketEdgesEncloseTheirValues) {
  for (uint64_t v :
       {0ull, 1ull, 7ull, 8ull, 9ull, 15ull, 16ull, 1000ull, 123456789ull, 1ull << 40}) {
    const int b = LatencyHistogram::bucket_of(v);
    EXPECT_LE(v, LatencyHistogram::upper_edge(b)) << v;
    if (b > 0) {
      EXPECT_GT(v, LatencyHistogram::upper_edge(b - 1)) << v;
    }
  }
}

TEST(LatencyHistogram, PercentilesAreWithinOneEighthOfTheTruth) {
  LatencyHistogram h;
  for (int64_t v = 1; v <= 10000; ++v) h.record(v * 100);
  EXPECT_EQ(h.count(), 10000u);
  EXPECT_EQ(h.max_ns(), 1'000'000u);
  const double p50 = static_cast<double>(h.percentile_ns(0.5));
  const double p99 = static_cast<double>(h.percentile_ns(0.99));
  EXPECT_NEAR(p50, 500'000, 500'000 / 8.0);
  EXPECT_NEAR(p99, 990'000, 990'000 / 8.0);
}

TEST(LatencyHistogram, EmptyReportsZero) {
  LatencyHistogram h;
  EXPECT_EQ(h.percentile_ns(0.5), 0u);
}

}  // namespace
}  // namespace scancrew
