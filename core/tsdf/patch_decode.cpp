// decode_patch: a patch's fixed fields, its zstd frame and every count, index and code of
// its payload checked against the receiver's config before any block is decoded.

#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>

#include "core/tsdf/patch_codec_format.hpp"

namespace scancrew::tsdf {

using namespace patch_codec_detail;

namespace {

constexpr size_t kMaxVarintBytes = 5;  // an int32 as a zigzag varint

struct ByteReader {
  const std::vector<uint8_t>& in;
  size_t at = 0;
  size_t left() const { return in.size() - at; }
  template <class T>
  bool get(T& v) {
    if (left() < sizeof(T)) return false;
    std::memcpy(&v, in.data() + at, sizeof(T));
    at += sizeof(T);
    return true;
  }
  bool varint(int64_t& v) {
    uint64_t u = 0;
    for (size_t i = 0; i < kMaxVarintBytes; ++i) {
      if (left() == 0) return false;
      const uint8_t b = in[at++];
      u |= uint64_t{b & 0x7fu} << (7 * i);
      if ((b & 0x80) == 0) {
        if (u > UINT32_MAX) return false;
        v = static_cast<int64_t>(u >> 1) ^ -static_cast<int64_t>(u & 1);
        return true;
      }
    }
    return false;
  }
};

// The smallest and largest payload of n blocks.
size_t min_payload(uint64_t n, int weight_bytes) {
  return kHeaderBytes + n * (3 + kMaskBytes + 1 + weight_bytes);
}
size_t max_payload(uint64_t n, int weight_bytes) {
  return kHeaderBytes +
         n * (3 * kMaxVarintBytes + kMaskBytes + size_t{kBlockVoxels} * (1 + weight_bytes));
}

struct DCtxFree {
  void operator()(ZSTD_DCtx* c) const { ZSTD_freeDCtx(c); }
};

// Decompresses one zstd frame that must hold exactly raw_bytes. The output grows with what
// the frame really produces, so a forged size allocates nothing up front.
Result<std::vector<uint8_t>, std::string> decompress(const std::vector<uint8_t>& data,
                                                     uint32_t raw_bytes) {
  constexpr uint8_t kZstdMagic[4] = {0x28, 0xb5, 0x2f, 0xfd};
  if (data.size() < 6 || std::memcmp(data.data(), kZstdMagic, 4) != 0)
    return make_unexpected(std::string("data is not a zstd frame"));
  if ((data[4] & 0x04) == 0)
    return make_unexpected(std::string("zstd frame without a content checksum"));
  const unsigned long long content = ZSTD_getFrameContentSize(data.data(), data.size());
  if (content == ZSTD_CONTENTSIZE_ERROR)
    return make_unexpected(std::string("zstd frame header is corrupt"));
  if (content != ZSTD_CONTENTSIZE_UNKNOWN && content != raw_bytes)
    return make_unexpected("zstd frame holds " + std::to_string(content) +
                           " bytes, raw_bytes says " + std::to_string(raw_bytes));
  const size_t frame = ZSTD_findFrameCompressedSize(data.data(), data.size());
  if (ZSTD_isError(frame) != 0)
    return make_unexpected(std::string("zstd frame: ") + ZSTD_getErrorName(frame));
  if (frame != data.size())
    return make_unexpected(std::to_string(data.size() - frame) +
                           " trailing bytes after the zstd frame");

  std::unique_ptr<ZSTD_DCtx, DCtxFree> dctx(ZSTD_createDCtx());
  if (!dctx) return make_unexpected(std::string("zstd: out of memory"));
  std::vector<uint8_t> out(std::min<size_t>(raw_bytes, std::max<size_t>(64 << 10, 8 * frame)));
  ZSTD_inBuffer in{data.data(), data.size(), 0};
  size_t produced = 0;
  while (true) {
    ZSTD_outBuffer o{out.data(), out.size(), produced};
    const size_t r = ZSTD_decompressStream(dctx.get(), &o, &in);
    if (ZSTD_isError(r) != 0) return make_unexpected(std::string("zstd: ") + ZSTD_getErrorName(r));
    produced = o.pos;
    if (r == 0) break;  // the frame is complete and its checksum verified
    if (produced == out.size()) {
      if (out.size() >= raw_bytes)
        return make_unexpected("payload larger than raw_bytes (" + std::to_string(raw_bytes) + ")");
      out.resize(std::min<size_t>(raw_bytes, 2 * out.size()));
    } else if (in.pos == in.size) {
      return make_unexpected(std::string("zstd frame truncated"));
    }
  }
  if (produced != raw_bytes)
    return make_unexpected("payload of " + std::to_string(produced) + " bytes, raw_bytes says " +
                           std::to_string(raw_bytes));
  out.resize(produced);
  return out;
}

}  // namespace

Result<DecodedPatch, std::string> decode_patch(const msg::TsdfPatch& patch,
                                               const TsdfConfig& expected,
                                               const PatchCodecConfig& codec) {
  auto fail = [&](const std::string& why) {
    return make_unexpected("patch " + std::to_string(patch.robot_id) + "/" +
                           std::to_string(patch.index) + " refused: " + why);
  };
  if (auto problem = codec.validate(); !problem.empty()) return fail(problem);
  auto near = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b); };

  // the fixed fields, against the receiver's map and each other
  if (patch.patch_id != make_patch_id(patch.robot_id, patch.index))
    return fail("patch_id " + std::to_string(patch.patch_id) + " is not (robot_id << 32) | index");
  if (!near(patch.voxel_size_m, expected.voxel_m))
    return fail("voxel size " + std::to_string(patch.voxel_size_m) + " m, this map's is " +
                std::to_string(expected.voxel_m) + " m");
  if (!near(patch.truncation_m, expected.truncation_m))
    return fail("truncation " + std::to_string(patch.truncation_m) + " m, this map's is " +
                std::to_string(expected.truncation_m) + " m");
  if (patch.block_count > codec.max_blocks)
    return fail(std::to_string(patch.block_count) + " blocks, more than max_blocks " +
                std::to_string(codec.max_blocks));
  if (patch.raw_bytes > kMaxRawBytes)
    return fail("raw_bytes " + std::to_string(patch.raw_bytes) + " exceeds 512 MiB");
  if (patch.raw_bytes < min_payload(patch.block_count, 1) ||
      patch.raw_bytes > max_payload(patch.block_count, 2))
    return fail("raw_bytes " + std::to_string(patch.raw_bytes) + " cannot hold " +
                std::to_string(patch.block_count) + " blocks");

  auto payload = decompress(patch.data, patch.raw_bytes);
  if (!payload) return fail(payload.error());
  const std::vector<uint8_t>& bytes = *payload;

  // header
  ByteReader r{bytes};
  char magic[4] = {};
  uint8_t version = 0, weight_bits = 0;
  uint16_t reserved = 0;
  uint32_t block_count = 0;
  WeightQuantiser quantiser;
  for (char& c : magic) r.get(c);
  r.get(version);
  r.get(weight_bits);
  r.get(reserved);
  r.get(block_count);
  r.get(quantiser.w_anchor);
  r.get(quantiser.w_max);
  r.get(quantiser.s);
  if (!r.get(quantiser.anchor_code)) return fail("payload shorter than its header");
  if (std::memcmp(magic, kMagic, 4) != 0 || reserved != 0)
    return fail("payload is not a TSDF patch");
  if (version != kPayloadVersion)
    return fail("payload version " + std::to_string(version) + ", expected " +
                std::to_string(kPayloadVersion));
  if (weight_bits < 8 || weight_bits > 16)
    return fail("weight_bits " + std::to_string(weight_bits));
  quantiser.bits = weight_bits;
  if (block_count != patch.block_count)
    return fail("payload holds " + std::to_string(block_count) + " blocks, block_count says " +
                std::to_string(patch.block_count));
  if (!(quantiser.w_anchor >= kMinWeight && quantiser.w_max <= kMaxWeight &&
        quantiser.w_max >= quantiser.w_anchor && std::isfinite(quantiser.s) && quantiser.s > 0 &&
        quantiser.s <= 1 && quantiser.anchor_code >= 1 &&
        quantiser.anchor_code <= quantiser.top_code()))
    return fail("weight quantiser out of range");
  const int weight_bytes = weight_bits > 8 ? 2 : 1;
  if (bytes.size() < min_payload(block_count, weight_bytes) ||
      bytes.size() > max_payload(block_count, weight_bytes))
    return fail("payload of " + std::to_string(bytes.size()) + " bytes cannot hold " +
                std::to_string(block_count) + " blocks");

  // indices: in range, strictly increasing (so no duplicate)
  DecodedPatch out;
  std::vector<BlockIndex> indices;
  indices.reserve(block_count);  // bounded by the payload size, checked above
  int64_t x = 0, y = 0, z = 0;
  for (uint32_t i = 0; i < block_count; ++i) {
    int64_t dx = 0, dy = 0, dz = 0;
    if (!r.varint(dx) || !r.varint(dy) || !r.varint(dz))
      return fail("block index " + std::to_string(i) + " is malformed or truncated");
    x += dx;
    y += dy;
    z += dz;
    if (std::max({std::abs(x), std::abs(y), std::abs(z)}) > kMaxBlockCoord)
      return fail("block index " + index_text(x, y, z) + " is outside the lattice");
    const BlockIndex b(static_cast<int>(x), static_cast<int>(y), static_cast<int>(z));
    if (i > 0 && !index_less(indices.back(), b))
      return fail("block index " + index_text(x, y, z) + " duplicated or out of order");
    indices.push_back(b);
  }

  // masks, then the planes, which must fill the rest exactly
  if (r.left() < size_t{block_count} * kMaskBytes) return fail("payload truncated in the masks");
  const uint8_t* masks = bytes.data() + r.at;
  r.at += size_t{block_count} * kMaskBytes;
  size_t observed = 0;
  for (uint32_t i = 0; i < block_count; ++i) {
    size_t in_block = 0;
    for (size_t j = 0; j < kMaskBytes; ++j)
      in_block += static_cast<size_t>(std::popcount(masks[i * kMaskBytes + j]));
    if (in_block == 0) return fail("block " + std::to_string(i) + " has no observed voxel");
    observed += in_block;
  }
  const size_t planes = observed * (1 + weight_bytes);
  if (r.left() < planes)
    return fail("payload truncated: " + std::to_string(observed) + " voxels need " +
                std::to_string(planes) + " bytes, " + std::to_string(r.left()) + " left");
  if (r.left() > planes) return fail(std::to_string(r.left() - planes) + " trailing bytes");

  const std::vector<float> weight_of = quantiser.table();
  const auto mu = static_cast<float>(patch.truncation_m);
  const uint8_t* distances = bytes.data() + r.at;
  const uint8_t* weights_hi = distances + observed;
  const uint8_t* weights_lo = weights_hi + observed;
  const uint32_t code_mask = quantiser.top_code();
  out.blocks.resize(block_count);
  size_t n = 0;
  int64_t code = 0;
  std::array<int32_t, kBlockVoxels> codes{};
  for (uint32_t i = 0; i < block_count; ++i) {
    DecodedBlock& db = out.blocks[i];
    db.index = indices[i];
    db.block.owner = patch.robot_id;
    codes.fill(-1);
    for (int v = 0; v < kBlockVoxels; ++v) {
      if ((masks[i * kMaskBytes + v / 8] & (1u << (v % 8))) == 0) continue;
      const auto q = static_cast<int8_t>(distances[n]);
      if (q == INT8_MIN) return fail("distance code -128 at voxel " + std::to_string(n));
      const uint32_t delta =
          weight_bytes == 1 ? weights_hi[n] : (uint32_t{weights_hi[n]} << 8) | weights_lo[n];
      code = (predict(codes, v, code) + delta) & code_mask;
      if (code == 0) return fail("weight code 0 at voxel " + std::to_string(n));
      codes[static_cast<size_t>(v)] = static_cast<int32_t>(code);
      db.block.voxels[static_cast<size_t>(v)] = {static_cast<float>(q) / 127.0F * mu,
                                                 weight_of[static_cast<size_t>(code)]};
      ++n;
    }
  }
  out.patch_id = patch.patch_id;
  out.robot_id = patch.robot_id;
  out.index = patch.index;
  out.T_world_patch = patch.T_world_patch;
  out.observed_voxels = observed;
  return out;
}

}  // namespace scancrew::tsdf
