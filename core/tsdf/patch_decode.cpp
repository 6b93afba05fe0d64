// decode_patch: a patch's fixed fields, its zstd frame and every count, index and code of
// its payload checked against the receiver's config before any block is decoded.

#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <utility>

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

// Checks the patch's fixed fields against the receiver's config and each other.
Result<void, std::string> check_fixed_fields(const msg::TsdfPatch& patch,
                                             const TsdfConfig& expected,
                                             const PatchCodecConfig& codec) {
  auto near = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b); };

  // the fixed fields, against the receiver's map and each other
  if (patch.patch_id != make_patch_id(patch.robot_id, patch.index))
    return make_unexpected("patch_id " + std::to_string(patch.patch_id) +
                           " is not (robot_id << 32) | index");
  if (!near(patch.voxel_size_m, expected.voxel_m))
    return make_unexpected("voxel size " + std::to_string(patch.voxel_size_m) +
                           " m, this map's is " + std::to_string(expected.voxel_m) + " m");
  if (!near(patch.truncation_m, expected.truncation_m))
    return make_unexpected("truncation " + std::to_string(patch.truncation_m) +
                           " m, this map's is " + std::to_string(expected.truncation_m) + " m");
  if (patch.block_count > codec.max_blocks)
    return make_unexpected(std::to_string(patch.block_count) + " blocks, more than max_blocks " +
                           std::to_string(codec.max_blocks));
  if (patch.raw_bytes > kMaxRawBytes)
    return make_unexpected("raw_bytes " + std::to_string(patch.raw_bytes) + " exceeds 512 MiB");
  if (patch.raw_bytes < min_payload(patch.block_count, 1) ||
      patch.raw_bytes > max_payload(patch.block_count, 2))
    return make_unexpected("raw_bytes " + std::to_string(patch.raw_bytes) + " cannot hold " +
                           std::to_string(patch.block_count) + " blocks");
  return {};
}

// The payload header's fields that the rest of the payload is read with.
struct PayloadHeader {
  uint32_t block_count = 0;
  WeightQuantiser quantiser;
  int weight_bytes = 1;
};

// Reads the payload header and checks it against the patch's fields and the payload size.
Result<PayloadHeader, std::string> read_header(ByteReader& r, const msg::TsdfPatch& patch) {
  const std::vector<uint8_t>& bytes = r.in;

  // header
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
  if (!r.get(quantiser.anchor_code))
    return make_unexpected(std::string("payload shorter than its header"));
  if (std::memcmp(magic, kMagic, 4) != 0 || reserved != 0)
    return make_unexpected(std::string("payload is not a TSDF patch"));
  if (version != kPayloadVersion)
    return make_unexpected("payload version " + std::to_string(version) + ", expected " +
                           std::to_string(kPayloadVersion));
  if (weight_bits < 8 || weight_bits > 16)
    return make_unexpected("weight_bits " + std::to_string(weight_bits));
  quantiser.bits = weight_bits;
  if (block_count != patch.block_count)
    return make_unexpected("payload holds " + std::to_string(block_count) +
                           " blocks, block_count says " + std::to_string(patch.block_count));
  if (!(quantiser.w_anchor >= kMinWeight && quantiser.w_max <= kMaxWeight &&
        quantiser.w_max >= quantiser.w_anchor && std::isfinite(quantiser.s) && quantiser.s > 0 &&
        quantiser.s <= 1 && quantiser.anchor_code >= 1 &&
        quantiser.anchor_code <= quantiser.top_code()))
    return make_unexpected(std::string("weight quantiser out of range"));
  const int weight_bytes = weight_bits > 8 ? 2 : 1;
  if (bytes.size() < min_payload(block_count, weight_bytes) ||
      bytes.size() > max_payload(block_count, weight_bytes))
    return make_unexpected("payload of " + std::to_string(bytes.size()) + " bytes cannot hold " +
                           std::to_string(block_count) + " blocks");
  return PayloadHeader{block_count, quantiser, weight_bytes};
}

// Reads the block indices' varint deltas and checks them.
Result<std::vector<BlockIndex>, std::string> read_indices(ByteReader& r, uint32_t block_count) {
  // indices: in range, strictly increasing (so no duplicate)
  std::vector<BlockIndex> indices;
  indices.reserve(block_count);  // bounded by the payload size, checked above
  int64_t x = 0, y = 0, z = 0;
  for (uint32_t i = 0; i < block_count; ++i) {
    int64_t dx = 0, dy = 0, dz = 0;
    if (!r.varint(dx) || !r.varint(dy) || !r.varint(dz))
      return make_unexpected("block index " + std::to_string(i) + " is malformed or truncated");
    x += dx;
    y += dy;
    z += dz;
    if (std::max({std::abs(x), std::abs(y), std::abs(z)}) > kMaxBlockCoord)
      return make_unexpected("block index " + index_text(x, y, z) + " is outside the lattice");
    const BlockIndex b(static_cast<int>(x), static_cast<int>(y), static_cast<int>(z));
    if (i > 0 && !index_less(indices.back(), b))
      return make_unexpected("block index " + index_text(x, y, z) + " duplicated or out of order");
    indices.push_back(b);
  }
  return indices;
}

// Where the masks and the planes lie in the payload, and how many voxels they hold.
struct PayloadPlanes {
  const uint8_t* masks = nullptr;
  const uint8_t* distances = nullptr;
  size_t observed = 0;
};

// Reads the masks and checks that the planes fill the rest of the payload exactly.
Result<PayloadPlanes, std::string> read_masks(ByteReader& r, uint32_t block_count,
                                              int weight_bytes) {
  const std::vector<uint8_t>& bytes = r.in;

  // masks, then the planes, which must fill the rest exactly
  if (r.left() < size_t{block_count} * kMaskBytes)
    return make_unexpected(std::string("payload truncated in the masks"));
  const uint8_t* masks = bytes.data() + r.at;
  r.at += size_t{block_count} * kMaskBytes;
  size_t observed = 0;
  for (uint32_t i = 0; i < block_count; ++i) {
    size_t in_block = 0;
    for (size_t j = 0; j < kMaskBytes; ++j)
      in_block += static_cast<size_t>(std::popcount(masks[i * kMaskBytes + j]));
    if (in_block == 0)
      return make_unexpected("block " + std::to_string(i) + " has no observed voxel");
    observed += in_block;
  }
  const size_t planes = observed * (1 + weight_bytes);
  if (r.left() < planes)
    return make_unexpected("payload truncated: " + std::to_string(observed) + " voxels need " +
                           std::to_string(planes) + " bytes, " + std::to_string(r.left()) +
                           " left");
  if (r.left() > planes)
    return make_unexpected(std::to_string(r.left() - planes) + " trailing bytes");
  return PayloadPlanes{masks, bytes.data() + r.at, observed};
}

// Decodes every observed voxel's distance and weight code into the blocks.
Result<std::vector<DecodedBlock>, std::string> decode_blocks(const msg::TsdfPatch& patch,
                                                             const PayloadHeader& header,
                                                             const std::vector<BlockIndex>& indices,
                                                             const PayloadPlanes& planes) {
  const uint32_t block_count = header.block_count;
  const int weight_bytes = header.weight_bytes;
  const size_t observed = planes.observed;
  const uint8_t* masks = planes.masks;
  const std::vector<float> weight_of = header.quantiser.table();
  const auto mu = static_cast<float>(patch.truncation_m);
  const uint8_t* distances = planes.distances;
  const uint8_t* weights_hi = distances + observed;
  const uint8_t* weights_lo = weights_hi + observed;
  const uint32_t code_mask = header.quantiser.top_code();
  std::vector<DecodedBlock> blocks(block_count);
  size_t n = 0;
  int64_t code = 0;
  std::array<int32_t, kBlockVoxels> codes{};
  for (uint32_t i = 0; i < block_count; ++i) {
    DecodedBlock& db = blocks[i];
    db.index = indices[i];
    db.block.owner = patch.robot_id;
    codes.fill(-1);
    for (int v = 0; v < kBlockVoxels; ++v) {
      if ((masks[i * kMaskBytes + v / 8] & (1u << (v % 8))) == 0) continue;
      const auto q = static_cast<int8_t>(distances[n]);
      if (q == INT8_MIN) return make_unexpected("distance code -128 at voxel " + std::to_string(n));
      const uint32_t delta =
          weight_bytes == 1 ? weights_hi[n] : (uint32_t{weights_hi[n]} << 8) | weights_lo[n];
      code = (predict(codes, v, code) + delta) & code_mask;
      if (code == 0) return make_unexpected("weight code 0 at voxel " + std::to_string(n));
      codes[static_cast<size_t>(v)] = static_cast<int32_t>(code);
      db.block.voxels[static_cast<size_t>(v)] = {static_cast<float>(q) / 127.0F * mu,
                                                 weight_of[static_cast<size_t>(code)]};
      ++n;
    }
  }
  return blocks;
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
  if (auto fixed = check_fixed_fields(patch, expected, codec); !fixed) return fail(fixed.error());

  auto payload = decompress(patch.data, patch.raw_bytes);
  if (!payload) return fail(payload.error());
  const std::vector<uint8_t>& bytes = *payload;

  ByteReader r{bytes};
  auto header = read_header(r, patch);
  if (!header) return fail(header.error());
  auto indices = read_indices(r, header->block_count);
  if (!indices) return fail(indices.error());
  auto planes = read_masks(r, header->block_count, header->weight_bytes);
  if (!planes) return fail(planes.error());
  auto blocks = decode_blocks(patch, *header, *indices, *planes);
  if (!blocks) return fail(blocks.error());

  DecodedPatch out;
  out.blocks = std::move(*blocks);
  out.patch_id = patch.patch_id;
  out.robot_id = patch.robot_id;
  out.index = patch.index;
  out.T_world_patch = patch.T_world_patch;
  out.observed_voxels = planes->observed;
  return out;
}

}  // namespace scancrew::tsdf
