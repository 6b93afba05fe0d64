#pragma once

// Parameters of the TSDF (thesis 1.3.3, 2.4.1, 3.4.1; tables 2.1, 4.1, 5.3). Read from a
// component's params (tsdf_mapper) or set directly by benchmarks and tests.

#include <cstdint>
#include <string>

#include "core/enum_names.hpp"

namespace scancrew::tsdf {

// How a measurement is weighted: 1/z² (thesis 3.4.1) or 1.
enum class TsdfWeight : uint8_t { kInverseSquare, kConstant };

inline constexpr EnumNames<TsdfWeight, 2> kTsdfWeightNames = {
    {{TsdfWeight::kInverseSquare, "inverse_square"}, {TsdfWeight::kConstant, "constant"}}};

struct TsdfConfig {
  double voxel_m = 0.2;       // r_v
  double truncation_m = 0.6;  // μ (eq. 1.3); 3 voxels by default
  double w_th = 0.3;          // W_th: a voxel is known when w ≥ W_th
  double max_weight = 50.0;   // w saturates here (thesis 1.3.3: "up to a maximum amount")
  double min_range_m = 0.3;   // depth outside [min, max] is not integrated
  double max_range_m = 5.0;
  // A +inf pixel (REP 117: no return within the sensor's range) says the ray is empty up to
  // the range: with clearing on, voxels of that ray up to max_range_m − μ along the optical
  // axis are written empty (φ = μ), as voxblox's clearing rays. Off: +inf is skipped like
  // NaN. max_range_m must not exceed the sensor's own range then (docs/tsdf.md).
  bool clear_beyond_range = false;
  TsdfWeight weight = TsdfWeight::kInverseSquare;  // inverse_square (1/z², 3.4.1) | constant (1)
  int tile_px = 8;                                 // block selection: depth tiles of tile_px² px

  // Empty when valid, else what is wrong (names the parameter).
  std::string validate() const;
};

}  // namespace scancrew::tsdf
