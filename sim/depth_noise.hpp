#pragma once

// The depth noise model of thesis 2.6.1: each valid pixel gets Gaussian noise of standard
// deviation sigma(z) = |e_d| z^2 / (f B), then the map is smoothed with a 3x3 Gaussian
// kernel ([1 2 1]^T [1 2 1] / 16, over finite neighbours only). As ROS REP 117 has it,
// pixels nearer than min_range become NaN (no measurement) and pixels beyond max_range, or
// with nothing up to the far plane (NaN in), +inf (no return within range: the mapper may
// clear the ray, TsdfConfig::clear_beyond_range). Deterministic for a given generator state.

#include <cstdint>
#include <random>
#include <vector>

namespace scancrew::sim {

struct DepthNoiseParams {
  bool add_noise = true;
  double disparity_error_px = 0.1;
  double fx_px = 0, baseline_m = 0;
  bool smoothing = true;
  double min_range_m = 0, max_range_m = 0;
};

// sigma(z) of 2.6.1.
double depth_sigma_m(double z_m, double disparity_error_px, double fx_px, double baseline_m);

// In place; `scratch` is reused between calls (no allocation once sized).
void apply_depth_noise(std::vector<float>& depth_m, uint32_t width, uint32_t height,
                       const DepthNoiseParams& p, std::mt19937_64& rng,
                       std::vector<float>& scratch);

}  // namespace scancrew::sim
