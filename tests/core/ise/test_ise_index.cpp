#include <gtest/gtest.h>

#include "core/ise/ise_index.hpp"

namespace scancrew::ise {
namespace {

TEST(IseIndex, FindsEachVoxelsIdAndNoneElsewhereAcrossNegativeBlocks) {
  IseIndex index;
  EXPECT_TRUE(index.empty());
  // -1 and 0 sit in different blocks (floor division), as do 7 and 8
  EXPECT_TRUE(index.emplace({-1, 0, 0}, 4));
  EXPECT_TRUE(index.emplace({0, 0, 0}, 5));
  EXPECT_TRUE(index.emplace({7, -9, 8}, 6));
  EXPECT_EQ(index.size(), 3u);
  EXPECT_EQ(index.find({-1, 0, 0}), 4u);
  EXPECT_EQ(index.find({0, 0, 0}), 5u);
  EXPECT_EQ(index.find({7, -9, 8}), 6u);
  EXPECT_EQ(index.find({1, 0, 0}), IseIndex::kNone);
  EXPECT_EQ(index.find({-9, 0, 0}), IseIndex::kNone);
  EXPECT_EQ(index.find({7, -1, 8}), IseIndex::kNone);
}

TEST(IseIndex, TheFirstIdOfAVoxelStands) {
  IseIndex index;
  EXPECT_TRUE(index.emplace({3, 3, 3}, 1));
  EXPECT_FALSE(index.emplace({3, 3, 3}, 2));
  EXPECT_FALSE(index.emplace({4, 3, 3}, IseIndex::kNone));
  EXPECT_EQ(index.find({3, 3, 3}), 1u);
  EXPECT_EQ(index.find({4, 3, 3}), IseIndex::kNone);
  EXPECT_EQ(index.size(), 1u);
}

TEST(IseIndex, ABlocksTableHoldsItsVoxelsAtTheirSlots) {
  IseIndex index;
  const VoxelIndex v{-3, 10, -17};  // block (-1, 1, -3), in-block (5, 2, 7)
  ASSERT_TRUE(index.emplace(v, 9));
  EXPECT_EQ(IseIndex::block_of(v), BlockIndex(-1, 1, -3));
  EXPECT_EQ(IseIndex::block_of(v), tsdf::block_of(v));
  const IseIndex::BlockIds* ids = index.block({-1, 1, -3});
  ASSERT_NE(ids, nullptr);
  EXPECT_EQ((*ids)[static_cast<size_t>(IseIndex::slot(v))], 9u);
  size_t held = 0;
  for (uint32_t id : *ids) held += id != IseIndex::kNone ? 1 : 0;
  EXPECT_EQ(held, 1u);
  EXPECT_EQ(index.block({0, 1, -3}), nullptr);
}

}  // namespace
}  // namespace scancrew::ise
