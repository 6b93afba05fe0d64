#include <gtest/gtest.h>

#include "executors/sample_pool.hpp"

namespace scancrew {
namespace {

TEST(SamplePool, HandsOutEverySlotOnceThenReportsExhaustion) {
  SamplePool<int> pool(3);
  auto a = pool.acquire(), b = pool.acquire(), c = pool.acquire();
  ASSERT_TRUE(a && b && c);
  EXPECT_NE(*a, *b);
  EXPECT_NE(*b, *c);
  EXPECT_FALSE(pool.acquire().has_value());
  EXPECT_EQ(pool.available(), 0u);
  pool.release(*a);
  pool.release(*b);
  pool.release(*c);
  EXPECT_EQ(pool.available(), 3u);
}

TEST(SamplePool, SlotReturnsOnlyWhenTheLastReferenceIsReleased) {
  SamplePool<int> pool(1);
  auto slot = pool.acquire();
  ASSERT_TRUE(slot);
  pool.retain(*slot);
  pool.retain(*slot);
  EXPECT_EQ(pool.refs(*slot), 3u);
  pool.release(*slot);
  pool.release(*slot);
  EXPECT_EQ(pool.available(), 0u);
  pool.release(*slot);
  EXPECT_EQ(pool.available(), 1u);
}

TEST(SamplePool, RecycledSlotKeepsItsValue) {
  SamplePool<std::vector<int>> pool(1);
  auto slot = pool.acquire();
  pool.at(*slot).resize(1000);
  const int* data = pool.at(*slot).data();
  pool.release(*slot);
  auto again = pool.acquire();
  ASSERT_TRUE(again);
  EXPECT_EQ(pool.at(*again).data(), data);
  EXPECT_GE(pool.at(*again).capacity(), 1000u);
  pool.release(*again);
}

}  // namespace
}  // namespace scancrew
