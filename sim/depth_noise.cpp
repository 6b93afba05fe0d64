#include "sim/depth_noise.hpp"

#include <cmath>
#include <limits>

namespace scancrew::sim {

double depth_sigma_m(double z_m, double disparity_error_px, double fx_px, double baseline_m) {
  return std::abs(disparity_error_px) * z_m * z_m / (fx_px * baseline_m);
}

void apply_depth_noise(std::vector<float>& depth_m, uint32_t width, uint32_t height,
                       const DepthNoiseParams& p, std::mt19937_64& rng,
                       std::vector<float>& scratch) {
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  constexpr float kBeyond = std::numeric_limits<float>::infinity();
  const size_t n = size_t{width} * height;
  // range gate first (REP 117): nearer than min is no measurement (NaN); beyond max, or
  // nothing up to the renderer's far plane (NaN in), is +inf: no return within range
  for (size_t i = 0; i < n; ++i) {
    const float z = depth_m[i];
    if (z < p.min_range_m)
      depth_m[i] = kNaN;
    else if (!(z <= p.max_range_m))
      depth_m[i] = kBeyond;
  }
  if (p.add_noise) {
    std::normal_distribution<double> unit(0.0, 1.0);
    for (size_t i = 0; i < n; ++i) {
      const float z = depth_m[i];
      if (!std::isfinite(z)) continue;
      depth_m[i] = static_cast<float>(
          z + unit(rng) * depth_sigma_m(z, p.disparity_error_px, p.fx_px, p.baseline_m));
    }
  }
  if (!p.smoothing) return;
  scratch.resize(n);
  static constexpr float kWeights[3] = {1.f, 2.f, 1.f};
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const float centre = depth_m[size_t{y} * width + x];
      if (!std::isfinite(centre)) {
        scratch[size_t{y} * width + x] = centre;
        continue;
      }
      float sum = 0, weight = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = static_cast<int>(y) + dy;
        if (yy < 0 || yy >= static_cast<int>(height)) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = static_cast<int>(x) + dx;
          if (xx < 0 || xx >= static_cast<int>(width)) continue;
          const float v = depth_m[static_cast<size_t>(yy) * width + static_cast<size_t>(xx)];
          if (!std::isfinite(v)) continue;
          const float w = kWeights[dy + 1] * kWeights[dx + 1];
          sum += w * v;
          weight += w;
        }
      }
      scratch[size_t{y} * width + x] = sum / weight;
    }
  }
  depth_m.swap(scratch);
}

}  // namespace scancrew::sim
