// ISE extraction (thesis 2.2 Definition 1, Definition 3, 2.4.2) on hand-built voxel maps
// whose answer is worked out by hand: exactly the expected ISEs across block borders and
// at negative coordinates, the 6- vs 18- vs 26-neighbourhood rules, scanned elements, and
// view directions pointing away from the occupied side.

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/ise/ise.hpp"
#include "tests/core/ise/voxel_scene.hpp"

namespace scancrew::ise {
namespace {

using test::key;
using test::Key;
using test::VoxelScene;
using tsdf::VoxelState;

// An occupied wall at x = −1 (y ∈ [−7, 10], z ∈ [−4, 5]) with a known-empty slab in front
// of it (x ∈ [0, 3], y ∈ [−6, 9], z ∈ [−3, 4]), one unknown voxel H = (0, 2, 1) inside the
// slab, and unknown space everywhere else. The slab spans blocks −1..1 in y and −1..0 in
// z; the wall is at local x = 7 of block −1, the slab's first layer at local x = 0 of
// block 0.
//
// By hand: only x = 0 has an occupied 18-neighbour (the wall voxel straight behind it,
// since the wall overhangs the slab by one voxel); of those, an ISE needs an unknown
// 6-neighbour: on the slab's y/z rim (outside the slab is unknown) or face-adjacent to H.
void build_slab(VoxelScene& scene) {
  scene.fill({-1, -7, -4}, {-1, 10, 5}, VoxelState::kOccupied);
  scene.fill({0, -6, -3}, {3, 9, 4}, VoxelState::kEmpty);
  scene.set({0, 2, 1}, VoxelState::kUnknown);
}

std::set<Key> slab_expected() {
  std::set<Key> out;
  for (int z = -3; z <= 4; ++z)
    for (int y = -6; y <= 9; ++y) {
      if (y == 2 && z == 1) continue;  // H itself is not empty
      const bool rim = y == -6 || y == 9 || z == -3 || z == 4;
      const bool next_to_hole = std::abs(y - 2) + std::abs(z - 1) == 1;
      if (rim || next_to_hole) out.insert({0, y, z});
    }
  return out;
}

TEST(IseExtraction, FindsExactlyTheHandComputedIsesAcrossBlockBorders) {
  VoxelScene scene;
  build_slab(scene);
  const auto snap = scene.snapshot();
  const std::set<Key> expected = slab_expected();
  ASSERT_EQ(expected.size(), 2u * 16 + 2u * 8 - 4 + 4);  // rim of 16 × 8, plus H's 4

  const std::vector<Ise> ises = test::extract_all(*snap);
  EXPECT_EQ(test::voxels_of(ises), expected);
  EXPECT_EQ(ises.size(), expected.size()) << "an ISE listed twice";
  // the rim crosses block borders at y = −1/0, y = 7/8 and z = −1/0
  EXPECT_TRUE(expected.contains({0, -1, -3}) && expected.contains({0, 0, -3}));
  EXPECT_TRUE(expected.contains({0, 7, 4}) && expected.contains({0, 8, 4}));
  for (const Ise& ise : ises) {
    EXPECT_TRUE(ise.center.isApprox(tsdf::voxel_center(ise.voxel, test::kVoxelM)));
  }

  // is_ise() agrees voxel by voxel, over a box one voxel larger than everything written
  for (int z = -5; z <= 6; ++z)
    for (int y = -8; y <= 11; ++y)
      for (int x = -2; x <= 4; ++x)
        EXPECT_EQ(is_ise(*snap, {x, y, z}), expected.contains({x, y, z}))
            << "voxel (" << x << ", " << y << ", " << z << ")";
}

TEST(IseExtraction, ExtractBlockListsOnlyItsOwnVoxelsInVoxelOrder) {
  VoxelScene scene;
  build_slab(scene);
  const auto snap = scene.snapshot();
  size_t total = 0;
  for (const BlockIndex& b : scene.blocks()) {
    const std::vector<Ise> list = extract_block(*snap, b);
    total += list.size();
    for (size_t i = 0; i < list.size(); ++i) {
      EXPECT_EQ(tsdf::block_of(list[i].voxel), b);
      if (i == 0) continue;
      const Eigen::Vector3i a = tsdf::local_of(list[i - 1].voxel);
      const Eigen::Vector3i c = tsdf::local_of(list[i].voxel);
      EXPECT_LT(tsdf::Block::index(a.x(), a.y(), a.z()), tsdf::Block::index(c.x(), c.y(), c.z()));
    }
  }
  EXPECT_EQ(total, slab_expected().size());
  EXPECT_TRUE(extract_block(*snap, {40, 40, 40}).empty());  // no block: all unknown
}

// A 7³ known-empty cube around v = (7, 0, −1): v's neighbours straddle the x = 7/8 block
// border and the z = −1/0 border. Its outer faces border unknown space, two voxels from
// anything a test writes next to v, so they give no ISE.
const VoxelIndex kV(7, 0, -1);
void build_cube(VoxelScene& scene) {
  scene.fill(kV - VoxelIndex::Constant(3), kV + VoxelIndex::Constant(3), VoxelState::kEmpty);
}

// The entry for voxel v in an extracted list, or null.
const Ise* find(const std::vector<Ise>& list, const VoxelIndex& v) {
  for (const Ise& ise : list)
    if (ise.voxel == v) return &ise;
  return nullptr;
}

TEST(IseDefinition, UnknownNeighbourOnlyAcrossAnEdgeOrCornerIsNotEnough) {
  VoxelScene scene;
  build_cube(scene);
  scene.set(kV + VoxelIndex(-1, 0, 0), VoxelState::kOccupied);  // face: condition c holds
  scene.set(kV + VoxelIndex(1, 1, 0), VoxelState::kUnknown);    // 18- but not 6-neighbour
  scene.set(kV + VoxelIndex(1, -1, 1), VoxelState::kUnknown);   // corner
  EXPECT_FALSE(is_ise(*scene.snapshot(), kV));
  // (its unknown voxels make other ISEs: (1,1,0)'s face neighbour (0,1,0) has the occupied
  // (−1,0,0) as an edge neighbour)
  std::vector<Ise> list = extract_block(*scene.snapshot(), tsdf::block_of(kV));
  EXPECT_EQ(find(list, kV), nullptr);
  EXPECT_NE(find(list, kV + VoxelIndex(0, 1, 0)), nullptr);

  scene.set(kV + VoxelIndex(0, 0, 1), VoxelState::kUnknown);  // a face neighbour, in block z=0
  EXPECT_TRUE(is_ise(*scene.snapshot(), kV));
  list = extract_block(*scene.snapshot(), tsdf::block_of(kV));
  EXPECT_NE(find(list, kV), nullptr);
}

TEST(IseDefinition, OccupiedNeighbourOnlyAtACornerDoesNotQualify) {
  VoxelScene scene;
  build_cube(scene);
  scene.set(kV + VoxelIndex(1, 0, 0), VoxelState::kUnknown);     // face, in block x=1
  scene.set(kV + VoxelIndex(1, 1, 1), VoxelState::kOccupied);    // corner: 26 only
  scene.set(kV + VoxelIndex(-1, -1, 1), VoxelState::kOccupied);  // corner
  EXPECT_FALSE(is_ise(*scene.snapshot(), kV));

  scene.set(kV + VoxelIndex(0, -1, -1), VoxelState::kOccupied);  // edge: an 18-neighbour
  EXPECT_TRUE(is_ise(*scene.snapshot(), kV));
}

TEST(IseDefinition, VoxelBelowTheWeightThresholdIsUnknownWhateverItsDistance) {
  VoxelScene scene;
  build_cube(scene);
  scene.set(kV + VoxelIndex(0, 1, 0), VoxelState::kOccupied);
  // negative distance, weight 0.4 < W_th = 0.5: unknown, not occupied
  scene.set_voxel(kV + VoxelIndex(0, -1, 0), {-0.05f, 0.4f});
  EXPECT_TRUE(is_ise(*scene.snapshot(), kV));
  // the ISE voxel itself under W_th is not empty
  scene.set_voxel(kV, {0.1f, 0.4f});
  EXPECT_FALSE(is_ise(*scene.snapshot(), kV));
}

TEST(IseDefinition, ScannedWhenEverySixNeighbourIsKnown) {
  VoxelScene scene;
  build_cube(scene);
  scene.set(kV + VoxelIndex(1, 1, 1), VoxelState::kUnknown);  // corner: does not matter
  scene.set(kV + VoxelIndex(0, 1, 1), VoxelState::kUnknown);  // edge: does not matter
  scene.set(kV + VoxelIndex(-1, 0, 0), VoxelState::kOccupied);
  EXPECT_TRUE(is_scanned(*scene.snapshot(), kV));
  scene.set(kV + VoxelIndex(0, 0, -1), VoxelState::kUnknown);
  EXPECT_FALSE(is_scanned(*scene.snapshot(), kV));
  EXPECT_TRUE(is_ise(*scene.snapshot(), kV));
  // the unknown neighbour observed: the element is scanned and no longer an ISE
  scene.set(kV + VoxelIndex(0, 0, -1), VoxelState::kOccupied);
  EXPECT_TRUE(is_scanned(*scene.snapshot(), kV));
  EXPECT_FALSE(is_ise(*scene.snapshot(), kV));
  // never observed: not scanned
  EXPECT_FALSE(is_scanned(*scene.snapshot(), {-100, -100, -100}));
}

// --- view directions -------------------------------------------------------------------

TEST(IseDirection, WallBehindGivesUnitDirectionAwayFromIt) {
  VoxelScene scene;
  build_slab(scene);
  const auto snap = scene.snapshot();
  const std::vector<Ise> ises = test::extract_all(*snap);
  ASSERT_FALSE(ises.empty());
  // every ISE has the whole wall plane x = −1 behind it: n̄ = +x exactly
  for (const Ise& ise : ises) {
    ASSERT_TRUE(ise.has_direction());
    EXPECT_NEAR(ise.direction.norm(), 1.0, 1e-12);
    EXPECT_NEAR(ise.direction.x(), 1.0, 1e-12);
    const std::optional<Eigen::Vector3d> n = view_direction(*snap, ise.voxel);
    ASSERT_TRUE(n.has_value());
    EXPECT_TRUE(n->isApprox(ise.direction, 1e-12));
  }
}

TEST(IseDirection, PartialWallGivesTheHandComputedWeightedSum) {
  VoxelScene scene;
  build_cube(scene);
  // occupied at (−1,0,0), (−1,1,0), (−1,0,1); the unknown face neighbour does not weigh
  scene.set(kV + VoxelIndex(-1, 0, 0), VoxelState::kOccupied);
  scene.set(kV + VoxelIndex(-1, 1, 0), VoxelState::kOccupied);
  scene.set(kV + VoxelIndex(-1, 0, 1), VoxelState::kOccupied);
  scene.set(kV + VoxelIndex(0, -1, 0), VoxelState::kUnknown);
  const auto snap = scene.snapshot();
  ASSERT_TRUE(is_ise(*snap, kV));
  // Σ over all 26 unit offsets is 0, so n = −2·W_th·Σ_occupied (c − v)/|c − v|
  const double s = 1 / std::sqrt(2.0);
  const Eigen::Vector3d expected = Eigen::Vector3d(1 + 2 * s, -s, -s).normalized();
  const std::optional<Eigen::Vector3d> n = view_direction(*snap, kV);
  ASSERT_TRUE(n.has_value());
  EXPECT_TRUE(n->isApprox(expected, 1e-12)) << n->transpose();
  EXPECT_GT(n->x(), std::abs(n->y()) + std::abs(n->z()));  // +x dominates
}

TEST(IseDirection, WallAndFloorGiveTheDiagonalBetweenThem) {
  VoxelScene scene;
  build_cube(scene);
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b) {
      scene.set(kV + VoxelIndex(-1, a, b), VoxelState::kOccupied);  // wall, x = −1
      scene.set(kV + VoxelIndex(a, b, -1), VoxelState::kOccupied);  // floor, z = −1
    }
  scene.set(kV + VoxelIndex(0, 1, 0), VoxelState::kUnknown);
  const auto snap = scene.snapshot();
  ASSERT_TRUE(is_ise(*snap, kV));
  const std::optional<Eigen::Vector3d> n = view_direction(*snap, kV);
  ASSERT_TRUE(n.has_value());
  EXPECT_NEAR(n->norm(), 1.0, 1e-12);
  EXPECT_GT(n->x(), 0.5);
  EXPECT_NEAR(n->x(), n->z(), 1e-12);
  EXPECT_NEAR(n->y(), 0.0, 1e-12);
}

TEST(IseDirection, SymmetricOccupiedNeighboursGiveNoDirection) {
  VoxelScene scene;
  build_cube(scene);
  scene.set(kV + VoxelIndex(-1, 0, 0), VoxelState::kOccupied);
  scene.set(kV + VoxelIndex(1, 0, 0), VoxelState::kOccupied);
  scene.set(kV + VoxelIndex(0, 1, 0), VoxelState::kUnknown);
  const auto snap = scene.snapshot();
  ASSERT_TRUE(is_ise(*snap, kV));
  EXPECT_FALSE(view_direction(*snap, kV).has_value());
  const std::vector<Ise> list = extract_block(*snap, tsdf::block_of(kV));
  const Ise* ise = find(list, kV);
  ASSERT_NE(ise, nullptr);
  EXPECT_FALSE(ise->has_direction());
  EXPECT_EQ(ise->direction, Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace scancrew::ise
