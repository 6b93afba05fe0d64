#include "components/tsdf/ply_mesh.hpp"

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <system_error>
#include <vector>

namespace scancrew::tsdf {

namespace {

static_assert(std::endian::native == std::endian::little,
              "write_ply copies floats and ints as they are in memory");

std::string system_error_text() {
  return std::error_code(errno, std::generic_category()).message();  // thread-safe strerror
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

template <class T>
void append(std::vector<char>& out, const T& value) {
  const size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &value, sizeof(T));
}

}  // namespace

std::array<uint8_t, 3> owner_colour(uint32_t owner) {
  // Okabe & Ito's colour-blind safe set, then a few of Tableau 10
  static constexpr std::array<std::array<uint8_t, 3>, 12> kPalette = {{
      {230, 159, 0},
      {86, 180, 233},
      {0, 158, 115},
      {240, 228, 66},
      {0, 114, 178},
      {213, 94, 0},
      {204, 121, 167},
      {148, 103, 189},
      {140, 86, 75},
      {188, 189, 34},
      {23, 190, 207},
      {214, 39, 40},
  }};
  if (owner == 0) return {128, 128, 128};
  return kPalette[(owner - 1) % kPalette.size()];
}

Result<void, std::string> write_ply(const Mesh& mesh, const std::string& path, PlyColour colour) {
  const size_t n = mesh.vertices.size();
  if (mesh.normals.size() != n || (colour == PlyColour::kByOwner && mesh.owners.size() != n))
    return make_unexpected("cannot write " + path + ": the mesh has " + std::to_string(n) +
                           " vertices but " + std::to_string(mesh.normals.size()) +
                           " normals and " + std::to_string(mesh.owners.size()) + " owners");
  if (n > static_cast<size_t>(std::numeric_limits<int32_t>::max()))
    return make_unexpected("cannot write " + path + ": more vertices than int indices hold");
  for (const Triangle& t : mesh.triangles)
    for (uint32_t i : t)
      if (i >= n)
        return make_unexpected("cannot write " + path + ": a triangle refers to vertex " +
                               std::to_string(i) + " of " + std::to_string(n));

  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) return make_unexpected("cannot open " + path + ": " + system_error_text());

  const bool rgb = colour == PlyColour::kByOwner;
  std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment scancrew TSDF mesh\nelement vertex " +
      std::to_string(n) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n";
  if (rgb) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  header += "element face " + std::to_string(mesh.triangles.size()) +
            "\nproperty list uchar int vertex_indices\nend_header\n";

  // vertices then faces, through one buffer of about 64 KiB
  constexpr size_t kFlushBytes = 1 << 16;
  std::vector<char> buffer(header.begin(), header.end());
  buffer.reserve(kFlushBytes + 64);
  auto flush = [&](bool force) {
    if (buffer.empty() || (!force && buffer.size() < kFlushBytes)) return true;
    const bool ok = std::fwrite(buffer.data(), 1, buffer.size(), file.get()) == buffer.size();
    buffer.clear();
    return ok;
  };
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) append(buffer, mesh.vertices[i][k]);
    for (int k = 0; k < 3; ++k) append(buffer, mesh.normals[i][k]);
    if (rgb)
      for (uint8_t c : owner_colour(mesh.owners[i])) append(buffer, c);
    if (!flush(false)) return make_unexpected("cannot write " + path + ": " + system_error_text());
  }
  for (const Triangle& t : mesh.triangles) {
    append(buffer, uint8_t{3});
    for (uint32_t i : t) append(buffer, static_cast<int32_t>(i));
    if (!flush(false)) return make_unexpected("cannot write " + path + ": " + system_error_text());
  }
  if (!flush(true)) return make_unexpected("cannot write " + path + ": " + system_error_text());
  std::FILE* f = file.release();
  if (std::fclose(f) != 0)
    return make_unexpected("cannot write " + path + ": " + system_error_text());
  return {};
}

}  // namespace scancrew::tsdf
