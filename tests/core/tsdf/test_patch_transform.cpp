// A decoded patch moved by a rigid correction (core/tsdf/patch_transform.hpp): a whole-voxel
// shift moves every value exactly; a turned and shifted linear field is resampled exactly
// (trilinear interpolation reproduces linear functions).
#include <gtest/gtest.h>

#include <cmath>

#include "core/tsdf/patch_transform.hpp"
#include "tests/core/tsdf/sdf_scenes.hpp"

namespace scancrew::tsdf {
namespace {

constexpr double kVoxel = 0.1;

template <class Sdf>
DecodedPatch patch_of(const Sdf& sdf, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TsdfMap map(test::config(kVoxel));
  test::fill(map, sdf, lo, hi, /*weight=*/2.0F, /*owner=*/7);
  DecodedPatch patch;
  patch.robot_id = 7;
  for (const auto& [index, block] : map.blocks()) patch.blocks.push_back({index, *block});
  std::sort(patch.blocks.begin(), patch.blocks.end(),
            [](const DecodedBlock& a, const DecodedBlock& b) {
              return std::lexicographical_compare(a.index.data(), a.index.data() + 3,
                                                  b.index.data(), b.index.data() + 3);
            });
  return patch;
}

const Voxel* voxel_in(const DecodedPatch& patch, const VoxelIndex& g) {
  for (const DecodedBlock& b : patch.blocks)
    if (b.index == block_of(g)) {
      const Eigen::Vector3i l = local_of(g);
      return &b.block.at(l.x(), l.y(), l.z());
    }
  return nullptr;
}

TEST(PatchTransform, AWholeVoxelShiftMovesEveryValueExactly) {
  const auto sdf = [](const Eigen::Vector3d& p) { return std::min(p.z(), 1.5 - p.x()); };
  const DecodedPatch source = patch_of(sdf, {0, 0, -0.3}, {1.9, 0.7, 0.9});
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(kVoxel, 0, 0);
  const DecodedPatch moved = transform_patch(source, kVoxel, T);
  size_t compared = 0;
  for (const DecodedBlock& b : source.blocks)
    for (int z = 0; z < kBlockSide; ++z)
      for (int y = 0; y < kBlockSide; ++y)
        for (int x = 0; x < kBlockSide; ++x) {
          const Voxel& s = b.block.at(x, y, z);
          const Voxel* d = voxel_in(moved, b.index * kBlockSide + Eigen::Vector3i(x + 1, y, z));
          ASSERT_NE(d, nullptr);
          EXPECT_NEAR(d->distance_m, s.distance_m, 1e-6);
          EXPECT_NEAR(d->weight, s.weight, 1e-6);
          ++compared;
        }
  EXPECT_EQ(compared, source.blocks.size() * kBlockVoxels);
  EXPECT_EQ(moved.robot_id, 7u);
  EXPECT_EQ(moved.blocks.front().block.owner, 7u);
}

TEST(PatchTransform, ATurnedLinearFieldIsResampledExactly) {
  const auto sdf = [](const Eigen::Vector3d& p) {
    return 0.04 * p.x() - 0.03 * p.y() + 0.05 * p.z();
  };
  const DecodedPatch source = patch_of(sdf, {-0.8, -0.8, -0.8}, {0.7, 0.7, 0.7});
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.17, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.037, -0.052, 0.011);
  const DecodedPatch moved = transform_patch(source, kVoxel, T);
  const Eigen::Isometry3d inverse = T.inverse();
  size_t written = 0;
  for (const DecodedBlock& b : moved.blocks)
    for (int z = 0; z < kBlockSide; ++z)
      for (int y = 0; y < kBlockSide; ++y)
        for (int x = 0; x < kBlockSide; ++x) {
          const Voxel& v = b.block.at(x, y, z);
          if (v.weight == 0) continue;
          const Eigen::Vector3d c =
              voxel_center(b.index * kBlockSide + Eigen::Vector3i(x, y, z), kVoxel);
          EXPECT_NEAR(v.distance_m, sdf(inverse * c), 1e-5);
          EXPECT_NEAR(v.weight, 2.0, 1e-5);
          ++written;
        }
  EXPECT_EQ(written, moved.observed_voxels);
  // the source's 16³ voxels, less at most a layer at each face
  EXPECT_GT(written, 13u * 13u * 13u);
}

}  // namespace
}  // namespace scancrew::tsdf
