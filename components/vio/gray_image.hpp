#pragma once

// GrayImage: a non-owning view of a row-major 8-bit image (a StereoFrame's left or right
// buffer). The viewed bytes must outlive every call that receives the view; nothing keeps
// a view past the call (the tracker copies the pixels it needs later).

#include <cstdint>

namespace scancrew::vio {

struct GrayImage {
  const uint8_t* data = nullptr;
  int width = 0, height = 0;  // pixels; stride == width

  bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
};

}  // namespace scancrew::vio
