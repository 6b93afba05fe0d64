#pragma once

// PNG files for people to look at: grayscale, RGB, and depth maps coloured by distance.

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace scancrew::sim {

// channels: 1 (gray) or 3 (RGB), rows top-down.
Result<void, std::string> write_png(const std::string& path, const std::vector<uint8_t>& pixels,
                                    uint32_t width, uint32_t height, int channels);
// Depth in metres -> RGB (near warm, far cool over [min_m, max_m]); NaN is black.
std::vector<uint8_t> colorize_depth(const std::vector<float>& depth_m, float min_m, float max_m);

}  // namespace scancrew::sim
