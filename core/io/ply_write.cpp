#include <bit>
#include <cerrno>
#include <cstdio>
#include <limits>
#include <memory>
#include <system_error>

#include "core/io/ply.hpp"

namespace scancrew::io {

namespace {

std::string system_error_text() {
  return std::error_code(errno, std::generic_category()).message();  // thread-safe strerror
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// A value as its little-endian bytes, whatever the machine's byte order.
void put_le(uint32_t bits, std::vector<char>& out) {
  for (int i = 0; i < 4; ++i, bits >>= 8U) out.push_back(static_cast<char>(bits & 0xFFU));
}

// Empty when the arrays fit together, else what is wrong.
std::string check(const PlyData& d) {
  if (d.positions.size() % 3 != 0) return "positions: not three values a vertex";
  const size_t n = d.positions.size() / 3;
  if ((d.mesh || !d.normals.empty()) && d.normals.size() != 3 * n)
    return std::to_string(n) + " vertices but " + std::to_string(d.normals.size() / 3) + " normals";
  if (!d.colours.empty() && d.colours.size() != 3 * n)
    return std::to_string(n) + " vertices but " + std::to_string(d.colours.size() / 3) + " colours";
  if (d.triangles.size() % 3 != 0) return "triangles: not three indices a triangle";
  if (n > static_cast<size_t>(std::numeric_limits<int32_t>::max()))
    return "more vertices than int indices hold";
  for (const uint32_t i : d.triangles)
    if (i >= n)
      return "a triangle refers to vertex " + std::to_string(i) + " of " + std::to_string(n);
  for (const auto& c : d.comments)
    if (c.find_first_of("\r\n") != std::string::npos) return "a comment holds a line break";
  return {};
}

std::string header(const PlyData& d) {
  std::string h = "ply\nformat binary_little_endian 1.0\n";
  for (const auto& c : d.comments) h += "comment " + c + "\n";
  h += "element vertex " + std::to_string(d.positions.size() / 3) +
       "\nproperty float x\nproperty float y\nproperty float z\n";
  if (d.mesh || !d.normals.empty())
    h += "property float nx\nproperty float ny\nproperty float nz\n";
  if (!d.colours.empty()) h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (d.mesh || !d.triangles.empty())
    h += "element face " + std::to_string(d.triangles.size() / 3) +
         "\nproperty list uchar int vertex_indices\n";
  return h + "end_header\n";
}

}  // namespace

Result<void, std::string> write_ply(const std::string& path, const PlyData& d) {
  if (const std::string e = check(d); !e.empty())
    return make_unexpected("cannot write " + path + ": " + e);
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) return make_unexpected("cannot open " + path + ": " + system_error_text());

  // the header, vertices then faces, through one buffer of about 64 KiB
  constexpr size_t kFlushBytes = 1 << 16;
  const std::string head = header(d);
  std::vector<char> buffer(head.begin(), head.end());
  buffer.reserve(kFlushBytes + 64);
  auto flush = [&](bool force) {
    if (buffer.empty() || (!force && buffer.size() < kFlushBytes)) return true;
    const bool ok = std::fwrite(buffer.data(), 1, buffer.size(), file.get()) == buffer.size();
    buffer.clear();
    return ok;
  };
  const auto failed = [&] {
    return make_unexpected("cannot write " + path + ": " + system_error_text());
  };
  const size_t n = d.positions.size() / 3;
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 3 * i; k < 3 * i + 3; ++k)
      put_le(std::bit_cast<uint32_t>(d.positions[k]), buffer);
    if (d.mesh || !d.normals.empty())
      for (size_t k = 3 * i; k < 3 * i + 3; ++k)
        put_le(std::bit_cast<uint32_t>(d.normals[k]), buffer);
    if (!d.colours.empty())
      for (size_t k = 3 * i; k < 3 * i + 3; ++k) buffer.push_back(static_cast<char>(d.colours[k]));
    if (!flush(false)) return failed();
  }
  for (size_t t = 0; t < d.triangles.size(); t += 3) {
    buffer.push_back(3);
    for (size_t k = t; k < t + 3; ++k) put_le(d.triangles[k], buffer);
    if (!flush(false)) return failed();
  }
  if (!flush(true)) return failed();
  if (std::fclose(file.release()) != 0) return failed();
  return {};
}

}  // namespace scancrew::io
