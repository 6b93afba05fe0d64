#include "report/coloured_ply.hpp"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string_view>

namespace scancrew::report {
namespace {

// The size in bytes of a PLY scalar type; 0: unknown.
size_t type_size(std::string_view t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

struct Layout {
  size_t vertices = 0, faces = 0;
  size_t stride = 0;                    // bytes of a vertex
  std::array<size_t, 3> xyz{}, rgb{};   // offsets in a vertex
  std::array<std::string, 3> xyz_type;  // their types
  bool has_xyz[3] = {false, false, false};
  int rgb_found = 0;                      // red, green, blue seen as uchar
  size_t count_size = 0, index_size = 0;  // the face list's types (0: no face element)
  size_t header_bytes = 0;
};

// Parses the header of text; an error message or "" with layout set.
std::string parse_header(const std::string& text, Layout& l) {
  if (text.rfind("ply\n", 0) != 0) return "not a PLY file";
  const size_t end = text.find("end_header\n");
  if (end == std::string::npos) return "no end_header";
  l.header_bytes = end + std::strlen("end_header\n");
  std::istringstream in(text.substr(0, end));
  std::string line, element;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string w, a, b, c, d;
    words >> w;
    if (w == "format" && (words >> a >> b, a != "binary_little_endian"))
      return "format '" + a + "' not read here (binary_little_endian only)";
    if (w == "element") {
      size_t n = 0;
      words >> element >> n;
      if (element != "vertex" && element != "face")
        return "element '" + element + "' not read here";
      (element == "vertex" ? l.vertices : l.faces) = n;
    }
    if (w != "property") continue;
    words >> a >> b;
    if (element == "face") {
      words >> c >> d;
      if (a != "list" || (d != "vertex_indices" && d != "vertex_index"))
        return "face property '" + line + "' not read here";
      l.count_size = type_size(b), l.index_size = type_size(c);
      if (l.count_size == 0 || l.count_size > 4 || l.index_size != 4)
        return "face list types '" + b + " " + c + "' not read here";
      continue;
    }
    const size_t size = type_size(a);
    if (element != "vertex" || size == 0) return "property '" + line + "' not read here";
    for (int k = 0; k < 3; ++k) {
      if (b == std::string(1, static_cast<char>('x' + k)))
        l.xyz[k] = l.stride, l.xyz_type[k] = a, l.has_xyz[k] = true;
      static constexpr std::array<std::string_view, 3> kColours = {"red", "green", "blue"};
      if (b == kColours[k] && size == 1) l.rgb[k] = l.stride, ++l.rgb_found;
    }
    l.stride += size;
  }
  if (!l.has_xyz[0] || !l.has_xyz[1] || !l.has_xyz[2]) return "no x, y, z vertex properties";
  return {};
}

float read_scalar(const char* p, const std::string& type) {
  if (type == "double" || type == "float64") {
    double v = 0;
    std::memcpy(&v, p, sizeof v);
    return static_cast<float>(v);
  }
  float v = 0;
  std::memcpy(&v, p, sizeof v);
  return v;
}

uint32_t read_uint(const char* p, size_t size) {
  uint32_t v = 0;
  std::memcpy(&v, p, size);  // little-endian host (x86-64, aarch64)
  return v;
}

}  // namespace

Result<ColouredPly, std::string> read_coloured_ply(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return make_unexpected("PLY file '" + path + "': cannot be read");
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  Layout l;
  if (std::string e = parse_header(text, l); !e.empty())
    return make_unexpected("PLY file '" + path + "': " + e);
  for (int k = 0; k < 3; ++k)
    if (l.xyz_type[k] != "float" && l.xyz_type[k] != "float32" && l.xyz_type[k] != "double" &&
        l.xyz_type[k] != "float64")
      return make_unexpected("PLY file '" + path + "': x, y, z of type " + l.xyz_type[k] +
                             " not read here");
  if (l.stride == 0 || (text.size() - l.header_bytes) / l.stride < l.vertices)
    return make_unexpected("PLY file '" + path + "': ends within its vertices");
  ColouredPly ply;
  ply.positions.resize(l.vertices);
  if (l.rgb_found == 3) ply.colours.resize(l.vertices);
  const char* p = text.data() + l.header_bytes;
  for (size_t i = 0; i < l.vertices; ++i, p += l.stride) {
    for (size_t k = 0; k < 3; ++k) ply.positions[i][k] = read_scalar(p + l.xyz[k], l.xyz_type[k]);
    if (l.rgb_found == 3)
      for (size_t k = 0; k < 3; ++k) ply.colours[i][k] = static_cast<uint8_t>(p[l.rgb[k]]);
  }
  const char* const end = text.data() + text.size();
  for (size_t f = 0; f < l.faces; ++f) {
    if (end - p < static_cast<std::ptrdiff_t>(l.count_size))
      return make_unexpected("PLY file '" + path + "': ends at face " + std::to_string(f));
    const uint32_t n = read_uint(p, l.count_size);
    p += l.count_size;
    if (static_cast<size_t>(end - p) < size_t{n} * l.index_size)
      return make_unexpected("PLY file '" + path + "': ends at face " + std::to_string(f));
    std::vector<uint32_t> idx(n);
    for (uint32_t k = 0; k < n; ++k, p += l.index_size) {
      idx[k] = read_uint(p, l.index_size);
      if (idx[k] >= l.vertices)
        return make_unexpected("PLY file '" + path + "': face " + std::to_string(f) +
                               " has vertex index " + std::to_string(idx[k]) + " out of range");
    }
    for (uint32_t k = 2; k < n; ++k) ply.triangles.push_back({idx[0], idx[k - 1], idx[k]});
  }
  return ply;
}

}  // namespace scancrew::report
