#include "sim/ply_writer.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <fstream>

namespace scancrew::sim {

namespace {

// a float as its 4 little-endian bytes, whatever the machine's byte order
void put_le(float f, char* out) {
  auto bits = std::bit_cast<uint32_t>(f);
  for (int i = 0; i < 4; ++i, bits >>= 8U) out[i] = static_cast<char>(bits & 0xFFU);
}

}  // namespace

Result<void, std::string> write_ply(const std::string& path,
                                    const std::vector<std::array<float, 3>>& points,
                                    const std::vector<std::array<float, 3>>& normals,
                                    const std::vector<std::string>& comments) {
  const bool with_normals = !normals.empty();
  if (with_normals && normals.size() != points.size())
    return make_unexpected("cannot write '" + path + "': " + std::to_string(points.size()) +
                           " points but " + std::to_string(normals.size()) + " normals");
  for (const auto& c : comments)
    if (c.find_first_of("\r\n") != std::string::npos)
      return make_unexpected("cannot write '" + path + "': a PLY comment holds a line break");
  std::ofstream out(path, std::ios::binary);
  if (!out) return make_unexpected("cannot write '" + path + "'");
  out << "ply\nformat binary_little_endian 1.0\n";
  for (const auto& c : comments) out << "comment " << c << "\n";
  out << "element vertex " << points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n";
  if (with_normals) out << "property float nx\nproperty float ny\nproperty float nz\n";
  out << "end_header\n";

  const size_t stride = with_normals ? 24 : 12;
  constexpr size_t kChunk = 1U << 16U;  // vertices per write
  std::vector<char> buffer(kChunk * stride);
  for (size_t first = 0; first < points.size(); first += kChunk) {
    const size_t n = std::min(kChunk, points.size() - first);
    char* p = buffer.data();
    for (size_t i = first; i < first + n; ++i) {
      for (const float f : points[i]) {
        put_le(f, p);
        p += 4;
      }
      if (!with_normals) continue;
      for (const float f : normals[i]) {
        put_le(f, p);
        p += 4;
      }
    }
    out.write(buffer.data(), static_cast<std::streamsize>(n * stride));
  }
  out.close();
  if (!out) return make_unexpected("cannot write '" + path + "': write failed (disk full?)");
  return {};
}

}  // namespace scancrew::sim
