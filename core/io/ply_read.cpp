#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "core/io/ply.hpp"

namespace scancrew::io {

namespace {

enum class Scalar : uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };
enum class Format : uint8_t { kAscii, kLittleEndian, kBigEndian };

std::optional<Scalar> parse_scalar(const std::string& name) {
  if (name == "char" || name == "int8") return Scalar::kInt8;
  if (name == "uchar" || name == "uint8") return Scalar::kUint8;
  if (name == "short" || name == "int16") return Scalar::kInt16;
  if (name == "ushort" || name == "uint16") return Scalar::kUint16;
  if (name == "int" || name == "int32") return Scalar::kInt32;
  if (name == "uint" || name == "uint32") return Scalar::kUint32;
  if (name == "float" || name == "float32") return Scalar::kFloat32;
  if (name == "double" || name == "float64") return Scalar::kFloat64;
  return std::nullopt;
}

size_t size_of(Scalar s) {
  switch (s) {
    case Scalar::kInt8:
    case Scalar::kUint8:
      return 1;
    case Scalar::kInt16:
    case Scalar::kUint16:
      return 2;
    case Scalar::kInt32:
    case Scalar::kUint32:
    case Scalar::kFloat32:
      return 4;
    case Scalar::kFloat64:
      return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Scalar type = Scalar::kFloat32;  // of the items, for a list
  bool list = false;
  Scalar count_type = Scalar::kUint8;
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
};

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  size_t body_offset = 0;  // first byte after "end_header\n"
};

// The header, line by line, up to end_header. Errors without the file name (added by the
// caller).
Result<Header, std::string> parse_header(const std::string& data) {
  if (data.rfind("ply\n", 0) != 0 && data.rfind("ply\r\n", 0) != 0)
    return make_unexpected(std::string("not a PLY file (it does not start with 'ply')"));
  Header h;
  bool has_format = false;
  size_t pos = 0;
  for (int line_no = 1;; ++line_no) {
    const size_t eol = data.find('\n', pos);
    if (eol == std::string::npos)
      return make_unexpected(std::string("the header has no end_header"));
    std::string line = data.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream in(line);
    std::string word;
    in >> word;
    const auto bad = [&](const std::string& why) {
      return make_unexpected("header line " + std::to_string(line_no) + " '" + line + "': " + why);
    };
    if (word == "end_header") break;
    if (word.empty() || word == "ply" || word == "comment" || word == "obj_info") continue;
    if (word == "format") {
      std::string format;
      in >> format;
      if (format == "ascii")
        h.format = Format::kAscii;
      else if (format == "binary_little_endian")
        h.format = Format::kLittleEndian;
      else if (format == "binary_big_endian")
        h.format = Format::kBigEndian;
      else
        return bad("unknown format");
      has_format = true;
    } else if (word == "element") {
      Element e;
      long long count = -1;
      if (!(in >> e.name >> count) || count < 0) return bad("expected 'element NAME COUNT'");
      e.count = static_cast<size_t>(count);
      h.elements.push_back(e);
    } else if (word == "property") {
      if (h.elements.empty()) return bad("a property before any element");
      Property p;
      std::string type;
      in >> type;
      if (type == "list") {
        std::string count_type, item_type;
        in >> count_type >> item_type >> p.name;
        const auto c = parse_scalar(count_type), t = parse_scalar(item_type);
        if (!c || !t || p.name.empty()) return bad("expected 'property list COUNT_TYPE TYPE NAME'");
        if (*c == Scalar::kFloat32 || *c == Scalar::kFloat64)
          return bad("a list count must be an integer type");
        p.list = true;
        p.count_type = *c;
        p.type = *t;
      } else {
        const auto t = parse_scalar(type);
        in >> p.name;
        if (!t || p.name.empty()) return bad("expected 'property TYPE NAME'");
        p.type = *t;
      }
      h.elements.back().properties.push_back(p);
    } else {
      return bad("unknown keyword '" + word + "'");
    }
  }
  if (!has_format) return make_unexpected(std::string("the header has no format line"));
  h.body_offset = pos;
  return h;
}

// Values of the body, one at a time, whatever the format.
class BodyReader {
 public:
  BodyReader(const std::string& data, size_t offset, Format format)
      : p_(data.data() + offset), end_(data.data() + data.size()), format_(format) {}

  size_t remaining() const { return static_cast<size_t>(end_ - p_); }

  // false at the end of the data or on a token that is not a number
  bool read(Scalar type, double& value) {
    return format_ == Format::kAscii ? read_ascii(value) : read_binary(type, value);
  }

 private:
  bool read_ascii(double& value) {
    while (p_ != end_ && std::isspace(static_cast<unsigned char>(*p_)) != 0) ++p_;
    if (p_ == end_) return false;
    const auto [next, ec] = std::from_chars(p_, end_, value);
    if (ec != std::errc()) return false;
    p_ = next;
    return true;
  }

  template <class T>
  T load() {
    std::array<char, sizeof(T)> bytes{};
    std::memcpy(bytes.data(), p_, sizeof(T));
    p_ += sizeof(T);
    const bool swap = (format_ == Format::kBigEndian) != (std::endian::native == std::endian::big);
    if (swap) std::reverse(bytes.begin(), bytes.end());
    return std::bit_cast<T>(bytes);
  }

  bool read_binary(Scalar type, double& value) {
    if (static_cast<size_t>(end_ - p_) < size_of(type)) return false;
    switch (type) {
      case Scalar::kInt8:
        value = load<int8_t>();
        break;
      case Scalar::kUint8:
        value = load<uint8_t>();
        break;
      case Scalar::kInt16:
        value = load<int16_t>();
        break;
      case Scalar::kUint16:
        value = load<uint16_t>();
        break;
      case Scalar::kInt32:
        value = load<int32_t>();
        break;
      case Scalar::kUint32:
        value = load<uint32_t>();
        break;
      case Scalar::kFloat32:
        value = load<float>();
        break;
      case Scalar::kFloat64:
        value = load<double>();
        break;
    }
    return true;
  }

  const char* p_;
  const char* end_;
  Format format_;
};

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

int index_of(const Element& e, const std::string& name) {
  for (size_t i = 0; i < e.properties.size(); ++i)
    if (e.properties[i].name == name && !e.properties[i].list) return static_cast<int>(i);
  return -1;
}

// the vertex and face elements, and where their coordinates and vertex indices are
struct MeshLayout {
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  std::array<int, 3> xyz{};  // property indices of x, y, z in the vertex element
  int indices = -1;          // property index of the face element's vertex list
};

// finds the mesh's layout in the header, or says what is missing
Result<MeshLayout, std::string> find_layout(const Header& header) {
  MeshLayout layout;
  const auto vertex = std::find_if(header.elements.begin(), header.elements.end(),
                                   [](const Element& e) { return e.name == "vertex"; });
  const auto face = std::find_if(header.elements.begin(), header.elements.end(),
                                 [](const Element& e) { return e.name == "face"; });
  if (vertex == header.elements.end()) return make_unexpected(std::string("no vertex element"));
  layout.xyz = {index_of(*vertex, "x"), index_of(*vertex, "y"), index_of(*vertex, "z")};
  if (std::find(layout.xyz.begin(), layout.xyz.end(), -1) != layout.xyz.end())
    return make_unexpected(std::string("the vertex element lacks x, y or z"));
  if (face == header.elements.end())
    return make_unexpected(std::string("no face element: a point cloud, not a mesh"));
  for (size_t i = 0; i < face->properties.size(); ++i) {
    const Property& p = face->properties[i];
    if (p.list && (p.name == "vertex_indices" || p.name == "vertex_index"))
      layout.indices = static_cast<int>(i);
  }
  if (layout.indices < 0)
    return make_unexpected(std::string("the face element has no list 'vertex_indices'"));
  layout.vertex = &*vertex;
  layout.face = &*face;
  return layout;
}

// reads one item of e: its scalars into values, the list `keep` (if any) into polygon;
// false when the data ends early or holds a non-number
bool read_item(BodyReader& reader, const Element& e, int keep, std::vector<double>& values,
               std::vector<double>& polygon) {
  for (size_t k = 0; k < e.properties.size(); ++k) {
    const Property& p = e.properties[k];
    if (!p.list) {
      if (!reader.read(p.type, values[k])) return false;
      continue;
    }
    double count = 0;
    // each item takes a byte at least: a larger count is a corrupt file, not a big face
    if (!reader.read(p.count_type, count) || count < 0 || count != std::floor(count) ||
        count > static_cast<double>(reader.remaining()))
      return false;
    const bool kept = static_cast<int>(k) == keep;
    if (kept) polygon.resize(static_cast<size_t>(count));
    for (size_t j = 0; j < static_cast<size_t>(count); ++j) {
      double v = 0;
      if (!reader.read(p.type, v)) return false;
      if (kept) polygon[j] = v;
    }
  }
  return true;
}

// adds face `item` (a polygon of vertex indices) as triangles; the problem if it is bad
std::string add_face(const std::vector<double>& polygon, size_t item, size_t vertex_count,
                     TriangleMesh& mesh) {
  if (polygon.size() < 3)
    return "face " + std::to_string(item) + " has " + std::to_string(polygon.size()) +
           " vertices, fewer than 3";
  for (const double v : polygon)
    if (!(v >= 0) || v >= static_cast<double>(vertex_count) || v != std::floor(v))
      return "face " + std::to_string(item) + " refers to vertex " + number(v) +
             ", but there are " + std::to_string(vertex_count) + " vertices";
  // a polygon as a fan of triangles around its first vertex
  for (size_t j = 1; j + 1 < polygon.size(); ++j)
    mesh.triangles.push_back({static_cast<uint32_t>(polygon[0]), static_cast<uint32_t>(polygon[j]),
                              static_cast<uint32_t>(polygon[j + 1])});
  return {};
}

Result<TriangleMesh, std::string> parse(const std::string& data) {
  auto header = parse_header(data);
  if (!header) return make_unexpected(header.error());
  auto found = find_layout(*header);
  if (!found) return make_unexpected(found.error());
  const MeshLayout& layout = *found;
  const Element* vertex = layout.vertex;
  const Element* face = layout.face;
  const std::array<int, 3>& xyz = layout.xyz;

  TriangleMesh mesh;
  // counts come from the file: reserve no more than its bytes could hold
  const size_t body = data.size() - header->body_offset;
  mesh.vertices.reserve(std::min(vertex->count, body / 3 + 1));
  mesh.triangles.reserve(std::min(face->count, body / 4 + 1));
  BodyReader reader(data, header->body_offset, header->format);
  std::vector<double> values, polygon;
  for (const Element& e : header->elements) {
    const auto ended = [&](size_t item) {
      return make_unexpected("the data ends early or holds a non-number: element '" + e.name +
                             "', item " + std::to_string(item) + " of " + std::to_string(e.count));
    };
    // an element without properties holds no data, whatever its count (2^62 of them looped
    // for centuries); one with properties takes a byte an item at least
    if (e.properties.empty()) continue;
    if (e.count > reader.remaining())
      return make_unexpected("element '" + e.name + "' counts " + std::to_string(e.count) +
                             " items, more than the " + std::to_string(reader.remaining()) +
                             " bytes left in the file");
    values.resize(e.properties.size());
    const int keep = &e == face ? layout.indices : -1;
    for (size_t item = 0; item < e.count; ++item) {
      if (!read_item(reader, e, keep, values, polygon)) return ended(item);
      if (&e == vertex) {
        mesh.vertices.push_back({values[static_cast<size_t>(xyz[0])],
                                 values[static_cast<size_t>(xyz[1])],
                                 values[static_cast<size_t>(xyz[2])]});
      } else if (&e == face) {
        if (std::string problem = add_face(polygon, item, vertex->count, mesh); !problem.empty())
          return make_unexpected(problem);
      }
    }
  }
  return mesh;
}

}  // namespace

Result<TriangleMesh, std::string> read_ply_mesh(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return make_unexpected("mesh file '" + path + "' does not exist or is not a file");
  std::ifstream in(path, std::ios::binary);
  std::string data(std::filesystem::file_size(path, ec), '\0');
  if (ec || !in.read(data.data(), static_cast<std::streamsize>(data.size())))
    return make_unexpected("cannot read mesh file '" + path + "'");
  auto mesh = parse(data);
  if (!mesh) return make_unexpected("mesh file '" + path + "': " + mesh.error());
  return mesh;
}

}  // namespace scancrew::io
