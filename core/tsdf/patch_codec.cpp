#include "core/tsdf/patch_codec.hpp"

#include <zstd.h>

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "interfaces/codec.hpp"

namespace scancrew::tsdf {

static_assert(std::endian::native == std::endian::little,
              "the patch payload is written as is: a big-endian port must byte-swap here");

namespace {

constexpr char kMagic[4] = {'S', 'C', 'T', 'P'};
constexpr uint8_t kPayloadVersion = 1;
constexpr size_t kHeaderBytes = 40;
constexpr size_t kMaskBytes = kBlockVoxels / 8;
constexpr size_t kMaxVarintBytes = 5;  // an int32 as a zigzag varint
constexpr uint32_t kMaxRawBytes = 512u << 20;
// block coordinates whose voxels' global indices fit an int32
constexpr int64_t kMaxBlockCoord = INT32_MAX / kBlockSide - 1;
// the weight codes reach this far below W_th (see the header)
constexpr double kWeightFloorRatio = 1e5;
constexpr double kMinWeight = 1e-30;  // floats, with room
constexpr double kMaxWeight = 1e30;

bool index_less(const BlockIndex& a, const BlockIndex& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

std::string index_text(int64_t x, int64_t y, int64_t z) {
  std::string s = std::to_string(x);  // (not "(" + …: GCC 12 warns falsely, -Wrestrict)
  s += ", " + std::to_string(y) + ", " + std::to_string(z) + ")";
  return s.insert(0, 1, '(');
}

// The logarithmic weight codes: top_code() is w ≥ w_max, codes [anchor_code, top) are the
// intervals [w_anchor·e^{ks}, w_anchor·e^{(k+1)s}), k = code − anchor_code, below them the
// same steps down to the floor. Code 0 is not used.
struct WeightQuantiser {
  int bits = 16;
  double w_anchor = 0;  // W_th as the map compares it (float)
  double w_max = 0;     // max_weight as float
  double s = 0;
  uint32_t anchor_code = 0;

  uint32_t top_code() const { return (1u << bits) - 1; }

  static WeightQuantiser make(const TsdfConfig& c, int bits) {
    WeightQuantiser q;
    q.bits = bits;
    q.w_anchor = static_cast<float>(c.w_th);
    q.w_max = static_cast<float>(c.max_weight);
    const double span = std::log(q.w_max / q.w_anchor);
    const uint32_t codes = q.top_code() - 1;  // 1 .. top − 1
    q.s = (span + std::log(kWeightFloorRatio)) / codes;
    uint32_t above = 0;  // intervals in [w_anchor, w_max)
    if (span > 0) {
      above = static_cast<uint32_t>(std::clamp(std::lround(span / q.s), 1L, long{codes} - 1));
      q.s = span / above;
    }
    q.anchor_code = q.top_code() - above;
    return q;
  }

  uint32_t encode(float w) const {
    if (w >= static_cast<float>(w_max)) return top_code();
    const double k = std::floor(std::log(w / w_anchor) / s);
    const auto lo = -static_cast<double>(anchor_code) + 1;
    const auto hi = static_cast<double>(top_code() - anchor_code) - 1;
    // the state w.r.t. W_th is decided as the map decides it, in float
    const double kk =
        w >= static_cast<float>(w_anchor) ? std::clamp(k, 0.0, hi) : std::clamp(k, lo, -1.0);
    return static_cast<uint32_t>(static_cast<int64_t>(anchor_code) + static_cast<int64_t>(kk));
  }

  // Every code's weight (index 0 unused).
  std::vector<float> table() const {
    std::vector<float> t(size_t{top_code()} + 1, 0.0F);
    const auto anchor = static_cast<float>(w_anchor);
    const auto max = static_cast<float>(w_max);
    for (uint32_t c = 1; c < top_code(); ++c) {
      const double k = static_cast<double>(c) - anchor_code + 0.5;
      auto w = static_cast<float>(w_anchor * std::exp(k * s));
      // keep each code on its side of W_th and below w_max, whatever the header says
      if (c >= anchor_code) w = std::max(w, anchor);
      if (c < anchor_code && w >= anchor) w = std::nextafter(anchor, 0.0F);
      t[c] = std::max(std::min(w, std::nextafter(max, 0.0F)), std::numeric_limits<float>::min());
    }
    t[top_code()] = max;
    return t;
  }
};

struct ByteWriter {
  std::vector<uint8_t>& out;
  template <class T>
  void put(const T& v) {
    const size_t at = out.size();
    out.resize(at + sizeof(T));
    std::memcpy(out.data() + at, &v, sizeof(T));
  }
  void varint(int32_t v) {
    auto u = (static_cast<uint32_t>(v) << 1) ^ static_cast<uint32_t>(v >> 31);  // zigzag
    while (u >= 0x80) {
      out.push_back(static_cast<uint8_t>(u | 0x80));
      u >>= 7;
    }
    out.push_back(static_cast<uint8_t>(u));
  }
};

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

// A voxel's weight code predicted from its neighbours in the block already coded (x−1,
// y−1, z−1): the Lorenzo predictor (a trilinear extrapolation) where all seven are observed,
// else a plane through three, else one neighbour, else the previous code. Weights are smooth
// in space, so the residuals are small and compress well. codes: −1 where not observed.
int64_t predict(const std::array<int32_t, kBlockVoxels>& codes, int i, int64_t previous) {
  const int x = i % kBlockSide, y = (i / kBlockSide) % kBlockSide,
            z = i / (kBlockSide * kBlockSide);
  auto at = [&](int dx, int dy, int dz) -> int64_t {
    if (x < dx || y < dy || z < dz) return -1;
    return codes[static_cast<size_t>(Block::index(x - dx, y - dy, z - dz))];
  };
  const int64_t a = at(1, 0, 0), b = at(0, 1, 0), c = at(0, 0, 1);
  const int64_t ab = at(1, 1, 0), ac = at(1, 0, 1), bc = at(0, 1, 1), abc = at(1, 1, 1);
  if (std::min({a, b, c, ab, ac, bc, abc}) >= 0) return a + b + c - ab - ac - bc + abc;
  if (std::min({a, b, ab}) >= 0) return a + b - ab;
  if (std::min({a, c, ac}) >= 0) return a + c - ac;
  if (std::min({b, c, bc}) >= 0) return b + c - bc;
  if (a >= 0) return a;
  if (b >= 0) return b;
  if (c >= 0) return c;
  return previous;
}

// The smallest and largest payload of n blocks.
size_t min_payload(uint64_t n, int weight_bytes) {
  return kHeaderBytes + n * (3 + kMaskBytes + 1 + weight_bytes);
}
size_t max_payload(uint64_t n, int weight_bytes) {
  return kHeaderBytes +
         n * (3 * kMaxVarintBytes + kMaskBytes + size_t{kBlockVoxels} * (1 + weight_bytes));
}

struct CCtxFree {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};
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

double weight_error_bound(const TsdfConfig& config, int weight_bits) {
  return std::expm1(WeightQuantiser::make(config, weight_bits).s / 2);
}

std::string PatchCodecConfig::validate() const {
  if (zstd_level < 1 || zstd_level > ZSTD_maxCLevel())
    return "zstd_level must be in [1, " + std::to_string(ZSTD_maxCLevel()) + "]";
  if (weight_bits < 8 || weight_bits > 16) return "weight_bits must be in [8, 16]";
  if (max_blocks < 1 || max_blocks > (1u << 20)) return "max_blocks must be in [1, 2^20]";
  return {};
}

Result<EncodeStats, std::string> encode_blocks(std::vector<BlockRef> blocks,
                                               const TsdfConfig& config, msg::TsdfPatch& out,
                                               const PatchCodecConfig& codec) {
  if (auto problem = config.validate(); !problem.empty()) return make_unexpected(problem);
  if (auto problem = codec.validate(); !problem.empty()) return make_unexpected(problem);
  if (!(config.w_th >= kMinWeight && config.max_weight <= kMaxWeight))
    return make_unexpected(
        std::string("w_th and max_weight must be in [1e-30, 1e30] to be encoded"));
  const auto mu = static_cast<float>(config.truncation_m);
  const WeightQuantiser quantiser = WeightQuantiser::make(config, codec.weight_bits);

  // the observed blocks, sorted, each checked
  size_t observed_voxels = 0;
  std::erase_if(blocks, [](const BlockRef& r) {
    if (r.block == nullptr) return true;
    return std::none_of(r.block->voxels.begin(), r.block->voxels.end(),
                        [](const Voxel& v) { return v.weight != 0; });
  });
  std::sort(blocks.begin(), blocks.end(),
            [](const BlockRef& a, const BlockRef& b) { return index_less(a.index, b.index); });
  if (blocks.size() > codec.max_blocks)
    return make_unexpected("patch has " + std::to_string(blocks.size()) +
                           " observed blocks, more than max_blocks " +
                           std::to_string(codec.max_blocks) + ": split it");
  for (size_t i = 0; i < blocks.size(); ++i) {
    const BlockIndex& b = blocks[i].index;
    if (b.cast<int64_t>().cwiseAbs().maxCoeff() > kMaxBlockCoord)
      return make_unexpected("block index " + index_text(b.x(), b.y(), b.z()) +
                             " is outside the lattice");
    if (i > 0 && blocks[i - 1].index == b)
      return make_unexpected("block " + index_text(b.x(), b.y(), b.z()) + " given twice");
    for (const Voxel& v : blocks[i].block->voxels) {
      if (v.weight == 0) continue;
      if (!(v.weight > 0 && std::isfinite(v.weight) && std::isfinite(v.distance_m)))
        return make_unexpected("block " + index_text(b.x(), b.y(), b.z()) +
                               " holds a voxel with distance " + std::to_string(v.distance_m) +
                               " and weight " + std::to_string(v.weight));
      ++observed_voxels;
    }
  }

  // the payload: header, indices, masks, then the distance and weight planes
  const int weight_bytes = codec.weight_bits > 8 ? 2 : 1;
  std::vector<uint8_t> payload;
  payload.reserve(kHeaderBytes + blocks.size() * (3 + kMaskBytes) +
                  observed_voxels * (1 + weight_bytes));
  ByteWriter w{payload};
  payload.insert(payload.end(), std::begin(kMagic), std::end(kMagic));
  w.put(kPayloadVersion);
  w.put(static_cast<uint8_t>(codec.weight_bits));
  w.put(uint16_t{0});
  w.put(static_cast<uint32_t>(blocks.size()));
  w.put(quantiser.w_anchor);
  w.put(quantiser.w_max);
  w.put(quantiser.s);
  w.put(quantiser.anchor_code);
  BlockIndex previous = BlockIndex::Zero();
  for (const BlockRef& r : blocks) {
    for (int i = 0; i < 3; ++i) w.varint(r.index[i] - previous[i]);
    previous = r.index;
  }
  for (const BlockRef& r : blocks) {
    std::array<uint8_t, kMaskBytes> mask{};
    for (size_t i = 0; i < kBlockVoxels; ++i)
      if (r.block->voxels[i].weight != 0) mask[i / 8] |= static_cast<uint8_t>(1u << (i % 8));
    payload.insert(payload.end(), mask.begin(), mask.end());
  }
  const size_t planes = payload.size();
  payload.resize(planes + observed_voxels * (1 + weight_bytes));
  uint8_t* distances = payload.data() + planes;
  uint8_t* weights_hi = distances + observed_voxels;  // the only plane with 8 bits
  uint8_t* weights_lo = weights_hi + observed_voxels;
  size_t n = 0;
  int64_t previous_code = 0;
  const uint32_t code_mask = quantiser.top_code();
  std::array<int32_t, kBlockVoxels> codes{};
  for (const BlockRef& r : blocks) {
    codes.fill(-1);
    for (int i = 0; i < kBlockVoxels; ++i) {
      const Voxel& v = r.block->voxels[static_cast<size_t>(i)];
      if (v.weight == 0) continue;
      const float d = std::clamp(v.distance_m, -mu, mu);
      long q = std::lround(d / mu * 127.0F);
      if (d > 0 && q == 0) q = 1;  // keep the sign: the voxel's state
      distances[n] = static_cast<uint8_t>(static_cast<int8_t>(q));
      const uint32_t code = quantiser.encode(v.weight);
      const auto delta = static_cast<uint32_t>(code - predict(codes, i, previous_code)) & code_mask;
      codes[static_cast<size_t>(i)] = static_cast<int32_t>(code);
      previous_code = code;
      if (weight_bytes == 1) {
        weights_hi[n] = static_cast<uint8_t>(delta);
      } else {
        weights_hi[n] = static_cast<uint8_t>(delta >> 8);
        weights_lo[n] = static_cast<uint8_t>(delta);
      }
      ++n;
    }
  }
  if (payload.size() > kMaxRawBytes)
    return make_unexpected("patch payload of " + std::to_string(payload.size()) +
                           " bytes exceeds 512 MiB: split it");

  // compressed, with a content checksum
  std::unique_ptr<ZSTD_CCtx, CCtxFree> cctx(ZSTD_createCCtx());
  if (!cctx) return make_unexpected(std::string("zstd: out of memory"));
  ZSTD_CCtx_setParameter(cctx.get(), ZSTD_c_compressionLevel, codec.zstd_level);
  ZSTD_CCtx_setParameter(cctx.get(), ZSTD_c_checksumFlag, 1);
  std::vector<uint8_t> data(ZSTD_compressBound(payload.size()));
  const size_t size =
      ZSTD_compress2(cctx.get(), data.data(), data.size(), payload.data(), payload.size());
  if (ZSTD_isError(size) != 0)
    return make_unexpected(std::string("zstd: ") + ZSTD_getErrorName(size));
  data.resize(size);

  out.voxel_size_m = config.voxel_m;
  out.truncation_m = config.truncation_m;
  out.block_count = static_cast<uint32_t>(blocks.size());
  out.raw_bytes = static_cast<uint32_t>(payload.size());
  out.data = std::move(data);

  EncodeStats stats;
  stats.blocks = blocks.size();
  stats.observed_voxels = observed_voxels;
  stats.raw_float_bytes = blocks.size() * kBlockVoxels * sizeof(Voxel);
  stats.payload_bytes = payload.size();
  stats.wire_bytes = msg::codec_detail::min_wire_size<msg::TsdfPatch>() + out.data.size();
  stats.ratio = stats.raw_float_bytes > 0 ? static_cast<double>(stats.wire_bytes) /
                                                static_cast<double>(stats.raw_float_bytes)
                                          : 0.0;
  return stats;
}

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
