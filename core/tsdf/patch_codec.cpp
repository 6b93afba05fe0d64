#include "core/tsdf/patch_codec.hpp"

#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "core/tsdf/patch_codec_format.hpp"
#include "interfaces/codec.hpp"

namespace scancrew::tsdf {

using namespace patch_codec_detail;

namespace {

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

struct CCtxFree {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};

// keeps the observed blocks, sorted, each checked; returns their observed voxel count
Result<size_t, std::string> check_blocks(std::vector<BlockRef>& blocks,
                                         const PatchCodecConfig& codec) {
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
  return observed_voxels;
}

// appends the payload's header, block indices and observed-voxel masks
void write_header(std::vector<uint8_t>& payload, const std::vector<BlockRef>& blocks,
                  const PatchCodecConfig& codec, const WeightQuantiser& quantiser) {
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
}

// appends the distance and weight planes of the blocks' observed voxels
void write_planes(std::vector<uint8_t>& payload, const std::vector<BlockRef>& blocks,
                  size_t observed_voxels, int weight_bytes, float mu,
                  const WeightQuantiser& quantiser) {
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
}

// the payload compressed, with a content checksum
Result<std::vector<uint8_t>, std::string> compress(const std::vector<uint8_t>& payload,
                                                   const PatchCodecConfig& codec) {
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
  return data;
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
  const Result<size_t, std::string> checked = check_blocks(blocks, codec);
  if (!checked.has_value()) return make_unexpected(checked.error());
  const size_t observed_voxels = *checked;

  // the payload: header, indices, masks, then the distance and weight planes
  const int weight_bytes = codec.weight_bits > 8 ? 2 : 1;
  std::vector<uint8_t> payload;
  payload.reserve(kHeaderBytes + blocks.size() * (3 + kMaskBytes) +
                  observed_voxels * (1 + weight_bytes));
  write_header(payload, blocks, codec, quantiser);
  write_planes(payload, blocks, observed_voxels, weight_bytes, mu, quantiser);
  if (payload.size() > kMaxRawBytes)
    return make_unexpected("patch payload of " + std::to_string(payload.size()) +
                           " bytes exceeds 512 MiB: split it");

  // compressed, with a content checksum
  Result<std::vector<uint8_t>, std::string> data = compress(payload, codec);
  if (!data.has_value()) return make_unexpected(data.error());

  out.voxel_size_m = config.voxel_m;
  out.truncation_m = config.truncation_m;
  out.block_count = static_cast<uint32_t>(blocks.size());
  out.raw_bytes = static_cast<uint32_t>(payload.size());
  out.data = std::move(data).value();

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

}  // namespace scancrew::tsdf
