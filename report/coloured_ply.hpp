#pragma once

// ColouredPly: a PLY file's vertices with their colours, and its triangles, for the report's
// 3D view and its per-robot surface (report/scene_view.hpp). Colours carry meaning in
// scancrew's own files: tsdf_mapper's mesh is coloured by the robot whose patches made each
// part (core/tsdf/ply_mesh.hpp), the ISE files by ISE class (core/ise/ise_ply.hpp);
// core/io/ply.hpp's reader skips colours, so they are read here.
//
// Read: format binary_little_endian 1.0 (what core/io/ply.hpp writes); element "vertex" with
// scalar properties of any type, of which x, y, z are required and red, green, blue (uchar)
// optional; element "face" (optional) with a list "vertex_indices" of uchar/ushort/uint
// count and int/uint indices, polygons split into fans; no other element.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace scancrew::report {

struct ColouredPly {
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<uint8_t, 3>> colours;  // one per vertex, or empty: no colours
  std::vector<std::array<uint32_t, 3>> triangles;
};

// Errors name the file and the cause: unreadable, not a PLY, an unsupported format, element
// or property type, no x/y/z, data that ends early, an index out of range.
Result<ColouredPly, std::string> read_coloured_ply(const std::string& path);

}  // namespace scancrew::report
