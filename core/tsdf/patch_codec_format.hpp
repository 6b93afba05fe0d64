#pragma once

// The patch payload's layout (patch_codec.hpp, the header comment) as the encoder
// (patch_codec.cpp) and the decoder (patch_decode.cpp) share it: its sizes and limits, the
// block order, the logarithmic weight codes and the weight-code predictor. Private to
// core/tsdf.

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/tsdf/patch_codec.hpp"

namespace scancrew::tsdf {

static_assert(std::endian::native == std::endian::little,
              "the patch payload is written as is: a big-endian port must byte-swap here");

namespace patch_codec_detail {

inline constexpr char kMagic[4] = {'S', 'C', 'T', 'P'};
inline constexpr uint8_t kPayloadVersion = 1;
inline constexpr size_t kHeaderBytes = 40;
inline constexpr size_t kMaskBytes = kBlockVoxels / 8;
inline constexpr uint32_t kMaxRawBytes = 512u << 20;
// block coordinates whose voxels' global indices fit an int32
inline constexpr int64_t kMaxBlockCoord = INT32_MAX / kBlockSide - 1;
// the weight codes reach this far below W_th (see the header)
inline constexpr double kWeightFloorRatio = 1e5;
inline constexpr double kMinWeight = 1e-30;  // floats, with room
inline constexpr double kMaxWeight = 1e30;

inline bool index_less(const BlockIndex& a, const BlockIndex& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

inline std::string index_text(int64_t x, int64_t y, int64_t z) {
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

// A voxel's weight code predicted from its neighbours in the block already coded (x−1,
// y−1, z−1): the Lorenzo predictor (a trilinear extrapolation) where all seven are observed,
// else a plane through three, else one neighbour, else the previous code. Weights are smooth
// in space, so the residuals are small and compress well. codes: −1 where not observed.
inline int64_t predict(const std::array<int32_t, kBlockVoxels>& codes, int i, int64_t previous) {
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

}  // namespace patch_codec_detail

}  // namespace scancrew::tsdf
