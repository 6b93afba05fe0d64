// The patch wire format (thesis 4.4.1): a patch decodes to its voxels within the stated
// quantisation error with every voxel's state kept, at ≤ 1/10 of the raw float blocks;
// corrupt, truncated, foreign and oversized patches are refused without allocating; fusing
// two patches equals integrating all their frames into one map and touches only their
// blocks.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <vector>

#include "core/tsdf/integrator.hpp"
#include "core/tsdf/patch_codec.hpp"
#include "core/tsdf/patch_fusion.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "interfaces/codec.hpp"

// The largest single allocation while tracking is on: proves a hostile patch is refused
// before its claimed sizes are allocated.
namespace {
std::atomic<bool> g_tracking{false};
std::atomic<size_t> g_largest{0};
}  // namespace

void* operator new(size_t n) {
  if (g_tracking.load(std::memory_order_relaxed)) {
    size_t seen = g_largest.load(std::memory_order_relaxed);
    while (n > seen && !g_largest.compare_exchange_weak(seen, n)) {
    }
  }
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, size_t /*n*/) noexcept {
  std::free(p);
}

namespace scancrew::tsdf {
namespace {

constexpr uint32_t kW = 320, kH = 256;
constexpr double kF = 160.0;  // 90° horizontal FOV

// A camera looking along +x (z forward in the camera frame), turned by yaw about z.
Eigen::Isometry3d camera(const Eigen::Vector3d& position, double yaw = 0) {
  Eigen::Matrix3d axes;
  axes.col(0) = Eigen::Vector3d(0, -1, 0);  // camera x: right
  axes.col(1) = Eigen::Vector3d(0, 0, -1);  // camera y: down
  axes.col(2) = Eigen::Vector3d(1, 0, 0);   // camera z: forward
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  T_world_cam.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * axes;
  T_world_cam.translation() = position;
  return T_world_cam;
}

// A room-like scene: a wall at x = 4.2 with a box standing out of its right part and a
// floor at z = −1.1 (depth along the optical axis of a camera looking along +x).
std::vector<float> scene_depth(const Eigen::Isometry3d& T_world_cam) {
  std::vector<float> d(static_cast<size_t>(kW) * kH);
  const Eigen::Vector3d o = T_world_cam.translation();
  for (uint32_t v = 0; v < kH; ++v)
    for (uint32_t u = 0; u < kW; ++u) {
      const Eigen::Vector3d ray_cam((u + 0.5 - kW / 2.0) / kF, (v + 0.5 - kH / 2.0) / kF, 1.0);
      const Eigen::Vector3d r = T_world_cam.linear() * ray_cam;  // z_cam = 1 along it
      double t = std::numeric_limits<double>::infinity();
      if (r.x() > 0) t = (4.2 - o.x()) / r.x();
      if (r.x() > 0) {
        const double tb = (3.4 - o.x()) / r.x();  // the box's front face
        const Eigen::Vector3d p = o + tb * r;
        if (p.y() < -0.5 && p.y() > -2.0 && p.z() < 0.3) t = std::min(t, tb);
      }
      if (r.z() < 0) t = std::min(t, (-1.1 - o.z()) / r.z());
      d[v * kW + u] = std::isfinite(t) && t > 0 ? static_cast<float>(t)
                                                : std::numeric_limits<float>::quiet_NaN();
    }
  return d;
}

struct Frames {
  std::vector<std::vector<float>> depth;
  std::vector<Eigen::Isometry3d> poses;

  DepthFrame frame(size_t i) const {
    DepthFrame f;
    f.depth_m = depth[i].data();
    f.size = depth[i].size();
    f.width = kW;
    f.height = kH;
    f.fx = f.fy = kF;
    f.cx = kW / 2.0;
    f.cy = kH / 2.0;
    f.T_world_cam = poses[i];
    return f;
  }
};

// n frames of a camera moving sideways and turning a little.
Frames frames(int n, double y0 = 0) {
  Frames f;
  for (int i = 0; i < n; ++i) {
    f.poses.push_back(camera({0.1 * i, y0 + 0.25 * i, 0.05 * i}, 0.05 * i - 0.1));
    f.depth.push_back(scene_depth(f.poses.back()));
  }
  return f;
}

TsdfConfig config() {
  TsdfConfig c;
  c.voxel_m = 0.2;
  c.truncation_m = 0.6;
  c.max_weight = 1000;  // not reached: fusion is then exactly integration
  return c;
}

void integrate(TsdfMap& map, const Frames& f, size_t from, size_t to) {
  Integrator integrator(map.config());
  for (size_t i = from; i < to; ++i) ASSERT_TRUE(integrator.integrate(map, f.frame(i)));
}

msg::TsdfPatch encoded(const TsdfMap& map, uint32_t robot, uint32_t index,
                       const PatchCodecConfig& codec = {}) {
  msg::TsdfPatch p;
  p.robot_id = robot;
  p.index = index;
  p.patch_id = make_patch_id(robot, index);
  auto stats = encode_patch(map.blocks(), map.config(), p, codec);
  EXPECT_TRUE(stats) << stats.error();
  return p;
}

TEST(PatchCodec, DecodesTheVoxelsWithinTheQuantisationErrorAndKeepsEveryState) {
  const TsdfConfig c = config();
  TsdfMap map(c);
  integrate(map, frames(5), 0, 5);
  for (const int bits : {12, 16, 8}) {  // the default first
    msg::TsdfPatch p;
    p.robot_id = 3;
    p.index = 7;
    p.patch_id = make_patch_id(3, 7);
    // timed warm: the best of a few runs
    using Ms = std::chrono::duration<double, std::milli>;
    double encode_ms = 1e9, decode_ms = 1e9;
    Result<EncodeStats, std::string> stats = make_unexpected(std::string("not run"));
    Result<DecodedPatch, std::string> decoded = make_unexpected(std::string("not run"));
    for (int run = 0; run < 5; ++run) {
      const auto t0 = std::chrono::steady_clock::now();
      stats = encode_patch(map.blocks(), c, p, {.weight_bits = bits});
      const auto t1 = std::chrono::steady_clock::now();
      ASSERT_TRUE(stats) << stats.error();
      decoded = decode_patch(p, c);
      const auto t2 = std::chrono::steady_clock::now();
      ASSERT_TRUE(decoded) << decoded.error();
      encode_ms = std::min(encode_ms, Ms(t1 - t0).count());
      decode_ms = std::min(decode_ms, Ms(t2 - t1).count());
    }
    std::printf(
        "[ patch    ] %d-bit weights: %zu blocks, %zu observed voxels, raw %zu B, payload %zu B, "
        "wire %zu B, ratio 1/%.1f; encode %.2f ms, decode %.2f ms\n",
        bits, stats->blocks, stats->observed_voxels, stats->raw_float_bytes, stats->payload_bytes,
        stats->wire_bytes, 1.0 / stats->ratio, encode_ms, decode_ms);
    EXPECT_GT(stats->blocks, 40u);
    EXPECT_LE(stats->wire_bytes * 10, stats->raw_float_bytes);
    EXPECT_EQ(stats->wire_bytes, msg::encode(p).size());
    EXPECT_EQ(decoded->patch_id, p.patch_id);
    EXPECT_EQ(decoded->observed_voxels, stats->observed_voxels);
    ASSERT_EQ(decoded->blocks.size(), stats->blocks);

    // every voxel: same observed set, same state, errors within the bounds
    const auto mu = static_cast<float>(c.truncation_m);
    const double w_error = weight_error_bound(c, bits);
    EXPECT_LT(w_error, bits == 16 ? 2e-4 : bits == 12 ? 3e-3 : 5e-2);
    const auto w_th = static_cast<float>(c.w_th);
    size_t flipped = 0, observed = 0;
    double max_d = 0, max_w = 0;
    for (const DecodedBlock& db : decoded->blocks) {
      const Block* b = map.find(db.index);
      ASSERT_NE(b, nullptr);
      EXPECT_EQ(db.block.owner, 3u);
      for (size_t i = 0; i < size_t{kBlockVoxels}; ++i) {
        const Voxel& a = b->voxels[i];
        const Voxel& d = db.block.voxels[i];
        ASSERT_EQ(a.weight > 0, d.weight > 0);
        if (a.weight == 0) continue;
        ++observed;
        if (state_of(a, w_th) != state_of(d, w_th)) ++flipped;
        const float bound = a.distance_m > 0 && a.distance_m < mu / 254 ? mu / 127 : mu / 254;
        EXPECT_LE(std::abs(a.distance_m - d.distance_m), bound * 1.0001F);
        max_d = std::max(max_d, static_cast<double>(std::abs(a.distance_m - d.distance_m)));
        max_w = std::max(max_w, std::abs(static_cast<double>(d.weight) / a.weight - 1));
      }
    }
    // every observed block of the map is in the patch
    size_t map_blocks = 0;
    for (const auto& [index, block] : map.blocks())
      for (const Voxel& v : block->voxels)
        if (v.weight > 0) {
          ++map_blocks;
          break;
        }
    EXPECT_EQ(map_blocks, decoded->blocks.size());
    EXPECT_EQ(observed, stats->observed_voxels);
    EXPECT_EQ(flipped, 0u);
    EXPECT_LE(max_d, c.truncation_m / 127);
    EXPECT_LE(max_w, w_error + 1e-6);
    std::printf(
        "[ patch    ] max errors: distance %.4f m (μ/254 = %.4f), weight %.2e relative (bound "
        "%.2e)\n",
        max_d, c.truncation_m / 254, max_w, w_error);
  }
}

TEST(PatchCodec, TheMessageRoundTripsThroughTheWireCodec) {
  TsdfMap map(config());
  integrate(map, frames(2), 0, 2);
  msg::TsdfPatch p = encoded(map, 2, 9);
  // a snapshot's blocks and a bare zstd level encode the same way
  msg::TsdfPatch from_snapshot = p;
  ASSERT_TRUE(encode_patch(map.snapshot()->blocks(), map.config(), from_snapshot, 3));
  EXPECT_EQ(from_snapshot.data, p.data);
  p.header.robot_id = 2;
  p.T_world_patch.position = {1, 2, 3};
  const std::vector<uint8_t> bytes = msg::encode(p);
  msg::TsdfPatch back;
  ASSERT_TRUE(msg::decode(bytes, back));
  EXPECT_EQ(msg::encode(back), bytes);
  EXPECT_EQ(back.data, p.data);
  auto decoded = decode_patch(back, map.config());
  ASSERT_TRUE(decoded) << decoded.error();
  EXPECT_EQ(decoded->T_world_patch.position.y, 2.0);
  EXPECT_EQ(decoded->index, 9u);
}

TEST(PatchCodec, AFlippedByteIsRefused) {
  TsdfMap map(config());
  integrate(map, frames(3), 0, 3);
  const msg::TsdfPatch good = encoded(map, 1, 0);
  const auto reference = decode_patch(good, map.config());
  ASSERT_TRUE(reference);
  // every byte of a short frame's start and end, and a spread over the rest
  const size_t n = good.data.size();
  size_t refused = 0, tried = 0;
  for (size_t i = 0; i < n; i += (i < 64 || i + 64 > n) ? 1 : n / 200 + 1) {
    msg::TsdfPatch bad = good;
    bad.data[i] ^= 0xff;
    ++tried;
    const auto r = decode_patch(bad, map.config());
    if (!r) {
      ++refused;
      EXPECT_NE(r.error().find("patch 1/0 refused: "), std::string::npos) << r.error();
      continue;
    }
    // a flip the frame does not depend on may pass, but then nothing changed
    ASSERT_EQ(r->blocks.size(), reference->blocks.size()) << i;
    for (size_t b = 0; b < r->blocks.size(); ++b)
      for (size_t v = 0; v < size_t{kBlockVoxels}; ++v) {
        ASSERT_EQ(r->blocks[b].block.voxels[v].distance_m,
                  reference->blocks[b].block.voxels[v].distance_m);
        ASSERT_EQ(r->blocks[b].block.voxels[v].weight, reference->blocks[b].block.voxels[v].weight);
      }
  }
  std::printf("[ patch    ] %zu of %zu flipped bytes refused\n", refused, tried);
  EXPECT_EQ(refused, tried);
  // the checksum itself
  msg::TsdfPatch bad = good;
  bad.data.back() ^= 0x01;
  const auto r = decode_patch(bad, map.config());
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("checksum"), std::string::npos) << r.error();
}

TEST(PatchCodec, ATruncatedPatchIsRefused) {
  TsdfMap map(config());
  integrate(map, frames(2), 0, 2);
  const msg::TsdfPatch good = encoded(map, 1, 0);
  for (size_t n = 0; n < good.data.size(); n += 1 + n / 8) {
    msg::TsdfPatch bad = good;
    bad.data.resize(n);
    EXPECT_FALSE(decode_patch(bad, map.config())) << n;
  }
  msg::TsdfPatch bad = good;
  bad.data.pop_back();
  const auto r = decode_patch(bad, map.config());
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("zstd"), std::string::npos) << r.error();
  bad = good;
  bad.data.push_back(0);
  const auto trailing = decode_patch(bad, map.config());
  ASSERT_FALSE(trailing);
  EXPECT_NE(trailing.error().find("trailing bytes"), std::string::npos) << trailing.error();
}

TEST(PatchCodec, APatchOfAnotherVoxelSizeOrTruncationIsRefused) {
  TsdfMap map(config());
  integrate(map, frames(2), 0, 2);
  const msg::TsdfPatch good = encoded(map, 1, 0);
  TsdfConfig other = config();
  other.voxel_m = 0.1;
  auto r = decode_patch(good, other);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("voxel size 0.200000 m, this map's is 0.100000 m"), std::string::npos)
      << r.error();
  other = config();
  other.truncation_m = 0.4;
  r = decode_patch(good, other);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("truncation"), std::string::npos) << r.error();
  // the fixed fields are checked against each other too
  msg::TsdfPatch bad = good;
  bad.block_count += 1;
  r = decode_patch(bad, map.config());
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("blocks"), std::string::npos) << r.error();
  bad = good;
  bad.index = 5;
  EXPECT_FALSE(decode_patch(bad, map.config()));
}

TEST(PatchCodec, AnOversizedPatchIsRefusedWithoutAllocating) {
  TsdfMap map(config());
  integrate(map, frames(2), 0, 2);
  const msg::TsdfPatch good = encoded(map, 1, 0);
  auto refused_small = [&](const msg::TsdfPatch& bad, const char* why) {
    g_largest = 0;
    g_tracking = true;
    const auto r = decode_patch(bad, map.config());
    g_tracking = false;
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().find(why), std::string::npos) << r.error();
    EXPECT_LT(g_largest.load(), size_t{1} << 20) << r.error();
  };
  msg::TsdfPatch bad = good;
  bad.raw_bytes = 0xffffffffu;
  refused_small(bad, "exceeds 512 MiB");
  bad = good;
  bad.raw_bytes = 400u << 20;  // under the cap but more than the blocks can fill
  refused_small(bad, "cannot hold");
  bad = good;
  bad.block_count = 60000;  // consistent with raw_bytes, but not with the frame
  bad.raw_bytes = 60000u * 1000;
  refused_small(bad, "zstd frame holds");
  bad = good;
  bad.block_count = 1u << 30;
  refused_small(bad, "max_blocks");
}

TEST(PatchFusion, FusingTwoPatchesEqualsIntegratingAllFrames) {
  const TsdfConfig c = config();
  const Frames f = frames(6);
  TsdfMap all(c), first(c), second(c);
  integrate(all, f, 0, 6);
  integrate(first, f, 0, 3);
  integrate(second, f, 3, 6);

  auto compare = [&](const TsdfMap& fused, double d_tol, double w_tol) {
    size_t observed = 0, flipped = 0;
    double max_d = 0, max_w = 0;
    ASSERT_EQ(fused.block_count(), all.block_count());
    for (const auto& [index, block] : all.blocks()) {
      const Block* b = fused.find(index);
      ASSERT_NE(b, nullptr);
      for (size_t i = 0; i < size_t{kBlockVoxels}; ++i) {
        const Voxel& a = block->voxels[i];
        const Voxel& v = b->voxels[i];
        ASSERT_EQ(a.weight > 0, v.weight > 0);
        if (a.weight == 0) continue;
        ++observed;
        max_d = std::max(max_d, static_cast<double>(std::abs(a.distance_m - v.distance_m)));
        max_w = std::max(max_w, std::abs(static_cast<double>(v.weight) / a.weight - 1));
        const auto w_th = static_cast<float>(c.w_th);
        // a weight on the threshold may differ by a float rounding
        if (state_of(a, w_th) != state_of(v, w_th) && std::abs(a.weight - w_th) > w_tol * w_th &&
            std::abs(a.distance_m) > d_tol)
          ++flipped;
      }
    }
    EXPECT_GT(observed, 10000u);
    EXPECT_LE(max_d, d_tol);
    EXPECT_LE(max_w, w_tol);
    EXPECT_EQ(flipped, 0u);
    std::printf("[ fusion   ] max differences: distance %.2e m, weight %.2e relative\n", max_d,
                max_w);
  };

  {  // the maps themselves: the same up to float rounding
    TsdfMap fused(c);
    fuse_map(fused, first.blocks(), 1);
    fuse_map(fused, second.blocks(), 2);
    compare(fused, 1e-5, 1e-5);
  }
  {  // through the wire: within the quantisation error (distance μ/254 each, weights 0.24 %)
    TsdfMap fused(c);
    auto a = decode_patch(encoded(first, 1, 0), c);
    auto b = decode_patch(encoded(second, 2, 0), c);
    ASSERT_TRUE(a && b);
    const FuseStats s1 = fuse_blocks(fused, *a);
    EXPECT_EQ(s1.new_blocks, s1.blocks);
    const FuseStats s2 = fuse_blocks(fused, *b);
    EXPECT_LT(s2.new_blocks, s2.blocks);
    compare(fused, c.truncation_m / 127 + 1e-5, weight_error_bound(c, 12) + 1e-5);
  }
}

TEST(PatchFusion, FusingTouchesOnlyThePatchBlocks) {
  const TsdfConfig c = config();
  TsdfMap map(c);
  integrate(map, frames(3), 0, 3);
  const auto before = map.snapshot();
  // a patch from elsewhere: a camera 3 m to the left sees part of the same wall
  TsdfMap other(c);
  Frames f = frames(2, 3.0);
  integrate(other, f, 0, 2);
  auto patch = decode_patch(encoded(other, 4, 1), c);
  ASSERT_TRUE(patch);
  const FuseStats stats = fuse_blocks(map, *patch);
  EXPECT_EQ(map.sequence(), before->sequence() + 1);
  EXPECT_EQ(stats.blocks, patch->blocks.size());

  size_t same = 0, written = 0;
  for (const auto& [index, block] : map.blocks()) {
    const BlockIndex b = index;
    const bool in_patch = std::any_of(patch->blocks.begin(), patch->blocks.end(),
                                      [&](const DecodedBlock& d) { return d.index == b; });
    if (in_patch) {
      ++written;
      EXPECT_EQ(block->modified, map.sequence());
      EXPECT_NE(block.get(), before->block(index));  // copied, the snapshot kept its own
    } else {
      ++same;
      EXPECT_EQ(block.get(), before->block(index));  // the very same block, untouched
    }
  }
  EXPECT_GT(same, 0u);
  EXPECT_EQ(written, patch->blocks.size());
  EXPECT_EQ(map.block_count(), before->block_count() + stats.new_blocks);
  EXPECT_GT(stats.new_blocks, 0u);
  EXPECT_LT(stats.new_blocks, stats.blocks);  // the patch overlaps the map

  // owners: a block new to the map is the patch's robot's
  for (const DecodedBlock& d : patch->blocks) {
    if (before->block(d.index) == nullptr) {
      EXPECT_EQ(map.find(d.index)->owner, 4u);
    }
  }
}

TEST(PatchFusion, ARefusedPatchLeavesTheMapUnchanged) {
  const TsdfConfig c = config();
  TsdfMap map(c);
  integrate(map, frames(2), 0, 2);
  const auto before = map.snapshot();
  msg::TsdfPatch bad = encoded(map, 5, 0);
  bad.data[bad.data.size() / 2] ^= 0x5a;
  ASSERT_FALSE(decode_patch(bad, c));  // nothing to fuse: the map is as it was
  EXPECT_EQ(map.sequence(), before->sequence());
  for (const auto& [index, block] : map.blocks()) EXPECT_EQ(block.get(), before->block(index));
}

TEST(PatchCodec, EncodingRefusesVoxelsThatAreNotFinite) {
  TsdfMap map(config());
  map.touch({1, 2, 3}).voxels[5] = {std::numeric_limits<float>::quiet_NaN(), 1.0F};
  msg::TsdfPatch p;
  const auto r = encode_patch(map.blocks(), map.config(), p);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("block (1, 2, 3) holds a voxel with distance nan"), std::string::npos)
      << r.error();
  EXPECT_TRUE(p.data.empty());  // out unchanged
}

TEST(PatchCodec, AnEmptyMapIsAnEmptyPatch) {
  TsdfMap map(config());
  msg::TsdfPatch p = encoded(map, 1, 2);
  EXPECT_EQ(p.block_count, 0u);
  auto decoded = decode_patch(p, map.config());
  ASSERT_TRUE(decoded) << decoded.error();
  EXPECT_TRUE(decoded->blocks.empty());
}

TEST(PatchCodecConfig, RefusesParametersOutOfRange) {
  EXPECT_EQ(PatchCodecConfig{}.validate(), "");
  EXPECT_EQ(PatchCodecConfig{.weight_bits = 17}.validate(), "weight_bits must be in [8, 16]");
  EXPECT_NE(PatchCodecConfig{.zstd_level = 0}.validate().find("zstd_level"), std::string::npos);
}

}  // namespace
}  // namespace scancrew::tsdf
