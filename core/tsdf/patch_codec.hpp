#pragma once

// The compact wire format of map patches (thesis 4.4.1) and their fusion into a map.
//
// A patch is the set of blocks a few depth maps observed. On the wire (msg::TsdfPatch::data)
// it is a zstd frame, with a content checksum, of this payload (little-endian):
//
//   header    "SCTP", u8 version 1, u8 weight_bits (8..16), u16 0, u32 block count,
//             f64 w_anchor, f64 w_max, f64 log step s, u32 anchor code    (40 bytes)
//   indices   per block, sorted by (x, y, z): zigzag varint deltas of x, y, z from the
//             previous block's (the first from 0)
//   masks     per block, 64 bytes: bit i set when voxel i (Block::index order) has w > 0
//   distances per observed voxel: int8 round(φ/μ·127), φ clamped to [−μ, μ]
//   weights   per observed voxel: the weight code less its prediction from the neighbours
//             already coded (Lorenzo predictor), mod 2^bits; with more than 8 bits, all
//             high bytes, then all low bytes
//
// Only observed voxels are stored, in planes of like values, so zstd compresses well: a
// typical patch (5 depth maps of 320×256, 0.2 m voxels, 12-bit weights) is about 1/17 of its
// blocks as raw floats (512 · 8 bytes a block); thesis target ≤ 1/10.
//
// Quantisation (errors are what the decoded voxel differs from the encoded one):
//   distance: |error| ≤ μ/254, except that a positive φ below μ/254 is stored as +1 code
//             (error < μ/127), so the sign, and with it the voxel's state, is kept.
//   weight:   logarithmic codes anchored at W_th and at max_weight: code c ≥ c_th exactly
//             when w ≥ W_th, the top code is w ≥ max_weight (decoded as max_weight, exact);
//             other codes decode to the geometric centre of their interval: relative error
//             ≤ e^{s/2} − 1 (weight_error_bound()). With W_th 0.3 and max_weight 50:
//             8 bits 3.3 %, 10 bits 0.82 %, 12 bits (default) 0.20 %, 16 bits 0.013 %.
//             Weights below W_th·10⁻⁵ are raised to that floor.
//   So every voxel's state (unknown, empty, occupied; block.hpp) is the same after
//   decoding, as long as the receiver's W_th is the sender's.
//
// Bad input: decode_patch() checks everything (voxel size and μ against the receiver's
// config, sizes before allocating, the zstd frame and its checksum, every count, index and
// code) and returns a named error; it never touches a map, so a refused patch leaves the map
// unchanged. fuse_blocks() (patch_fusion.hpp) then applies a decoded patch.
//
// Thread safety: the functions are reentrant; fusion writes the map (one writer, as
// TsdfMap requires).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "interfaces/map_msgs.hpp"

namespace scancrew::tsdf {

inline uint64_t make_patch_id(uint32_t robot_id, uint32_t index) {
  return (uint64_t{robot_id} << 32) | index;
}

struct PatchCodecConfig {
  int zstd_level = 3;              // 1 (fast) .. ZSTD_maxCLevel() (small)
  int weight_bits = 12;            // 8 .. 16: the weight's precision (see above)
  uint32_t max_blocks = 1u << 16;  // per patch (a decoded block is 4 KiB of voxels)
  // Empty when valid, else what is wrong (names the parameter).
  std::string validate() const;
};

// The largest relative error of a decoded weight (e^{s/2} − 1) for weights at or above
// W_th·10⁻⁵ (lower ones are raised to that floor).
double weight_error_bound(const TsdfConfig& config, int weight_bits);

struct EncodeStats {
  size_t blocks = 0;           // observed blocks in the patch
  size_t observed_voxels = 0;  // voxels with w > 0
  size_t raw_float_bytes = 0;  // blocks · 512 · 8: the blocks as floats
  size_t payload_bytes = 0;    // before compression (msg.raw_bytes)
  size_t wire_bytes = 0;       // the encoded message (msg::encode), all fields
  double ratio = 0;            // wire_bytes / raw_float_bytes
};

struct BlockRef {
  BlockIndex index;
  const Block* block = nullptr;
};

// Encodes the observed blocks (those with a voxel of w > 0) into out's payload fields:
// voxel_size_m, truncation_m, block_count, raw_bytes, data. The caller sets the others
// (header, patch_id, robot_id, index, T_world_patch). Fails on an invalid config, a
// non-finite or negative voxel value, a block index that does not fit the lattice, more than
// max_blocks observed blocks; out is then unchanged. Allocates the payload.
Result<EncodeStats, std::string> encode_blocks(std::vector<BlockRef> blocks,
                                               const TsdfConfig& config, msg::TsdfPatch& out,
                                               const PatchCodecConfig& codec = {});

// The blocks of a map (TsdfMap::blocks()) or of a snapshot (MapSnapshot::blocks()).
template <class B>
Result<EncodeStats, std::string> encode_patch(const BlockTable<B>& blocks, const TsdfConfig& config,
                                              msg::TsdfPatch& out,
                                              const PatchCodecConfig& codec = {}) {
  std::vector<BlockRef> refs;
  refs.reserve(blocks.size());
  for (const auto& [index, block] : blocks) refs.push_back({index, block.get()});
  return encode_blocks(std::move(refs), config, out, codec);
}
template <class B>
Result<EncodeStats, std::string> encode_patch(const BlockTable<B>& blocks, const TsdfConfig& config,
                                              msg::TsdfPatch& out, int zstd_level) {
  return encode_patch(blocks, config, out, PatchCodecConfig{.zstd_level = zstd_level});
}

struct DecodedBlock {
  BlockIndex index;
  Block block;  // owner: the patch's robot_id; modified: 0
};

struct DecodedPatch {
  uint64_t patch_id = 0;
  uint32_t robot_id = 0;
  uint32_t index = 0;
  msg::Pose3 T_world_patch;
  std::vector<DecodedBlock> blocks;  // sorted by index (x, y, z)
  size_t observed_voxels = 0;
};

// Decodes and checks a patch against the receiver's config: the voxel size and μ must be
// expected's (relative tolerance 1e-9). Refuses, with the cause named, anything else than
// a well-formed patch (see the header comment). Allocates the decoded blocks only after
// checking the sizes that bound them.
Result<DecodedPatch, std::string> decode_patch(const msg::TsdfPatch& patch,
                                               const TsdfConfig& expected,
                                               const PatchCodecConfig& codec = {});

}  // namespace scancrew::tsdf
