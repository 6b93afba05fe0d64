#include "sim/png_writer.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace scancrew::sim {

Result<void, std::string> write_png(const std::string& path, const std::vector<uint8_t>& pixels,
                                    uint32_t width, uint32_t height, int channels) {
  if (channels != 1 && channels != 3)
    return make_unexpected(std::string("write_png: channels must be 1 or 3"));
  if (pixels.size() < size_t{width} * height * channels)
    return make_unexpected(std::string("write_png: too few pixels"));
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return make_unexpected("cannot write '" + path + "'");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (png == nullptr || info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
    return make_unexpected("libpng failed writing '" + path + "'");
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, 8,
               channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (uint32_t y = 0; y < height; ++y) {
    // libpng's row pointer is not const-correct; png_write_row only reads the row
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-const-cast): libpng reads only
    auto* row = const_cast<png_bytep>(&pixels[size_t{y} * width * channels]);
    png_write_row(png, row);
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
  return {};
}

std::vector<uint8_t> colorize_depth(const std::vector<float>& depth_m, float min_m, float max_m) {
  std::vector<uint8_t> rgb(depth_m.size() * 3, 0);
  for (size_t i = 0; i < depth_m.size(); ++i) {
    const float z = depth_m[i];
    if (std::isnan(z)) continue;
    const float t = std::clamp((z - min_m) / (max_m - min_m), 0.0f, 1.0f);
    // a simple warm-to-cool ramp: red -> yellow -> cyan -> blue
    rgb[3 * i + 0] = static_cast<uint8_t>(255 * std::clamp(1.5f - 2.0f * t, 0.0f, 1.0f));
    rgb[3 * i + 1] =
        static_cast<uint8_t>(255 * std::clamp(1.0f - std::abs(2.0f * t - 0.8f), 0.0f, 1.0f));
    rgb[3 * i + 2] = static_cast<uint8_t>(255 * std::clamp(2.0f * t - 0.3f, 0.0f, 1.0f));
  }
  return rgb;
}

}  // namespace scancrew::sim
