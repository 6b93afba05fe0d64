#pragma once

// PLY files (Turk, "The PLY polygon file format", 1994), read and written here only: the
// scancrew meshes, point clouds and pictures (tsdf_mapper's mesh, the ground truth, the
// points a reconstruction missed, the ISEs) are written by write_ply; meshes from any
// reconstruction pipeline (Open3D, voxblox, nvblox, CloudCompare, MeshLab) are read by
// read_ply_mesh. Read here rather than with assimp (sim/mesh_io.hpp), which merges vertices,
// drops degenerate faces and refuses flat meshes: an evaluation must score the mesh exactly
// as written.
//
// Write: binary_little_endian 1.0; element vertex with float x y z, then float nx ny nz and
// uchar red green blue when given; element face (when triangles are given) as a uchar count
// and int vertex_indices. Readable by MeshLab, CloudCompare, Open3D and Blender.
//
// Read: format ascii, binary_little_endian or binary_big_endian; element "vertex" with
// scalar properties x, y, z of any type (other properties — normals, colours — skipped);
// element "face" with a list property "vertex_indices" (or "vertex_index") of any count and
// index types, polygons split into triangle fans; any other element skipped. A "face"
// element of 0 faces gives an empty mesh.

#include <cstdint>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "core/io/triangle_mesh.hpp"
#include "core/result.hpp"

namespace scancrew::io {

// What write_ply writes, as views on the caller's arrays (nothing is copied): three values a
// vertex, three indices a triangle.
struct PlyData {
  std::span<const float> positions;     // x y z per vertex
  std::span<const float> normals;       // empty, or nx ny nz per vertex
  std::span<const uint8_t> colours;     // empty, or red green blue per vertex
  std::span<const uint32_t> triangles;  // empty (a point cloud), or three vertex indices each
  std::vector<std::string> comments;    // a `comment` line of the header each (no line breaks)
  // A mesh: the header declares normals (then one per vertex is required) and the face
  // element even when there are none, so that an empty mesh reads back as a mesh.
  bool mesh = false;
};

// A view of n three-value items (std::array<float, 3>, Eigen::Vector3f, a triangle's indices)
// as 3n values, for PlyData.
template <class Item>
auto flat(const std::vector<Item>& items) {
  using T = std::remove_cv_t<std::remove_pointer_t<decltype(std::declval<const Item&>().data())>>;
  static_assert(sizeof(Item) == 3 * sizeof(T), "three values an item, no padding");
  return items.empty() ? std::span<const T>()
                       : std::span<const T>(items.front().data(), 3 * items.size());
}

// Writes data to path (replacing it). Errors name the path and the cause: arrays of
// inconsistent sizes, an index out of range, a comment with a line break, the system's
// reason when the file cannot be written (then it may be left partly written).
Result<void, std::string> write_ply(const std::string& path, const PlyData& data);

// Errors name the file and the cause: a missing file, not a PLY, an unsupported format or
// property type, no x/y/z, no face element (a point cloud), data that ends early (which
// element and which item), a vertex index out of range, a face of fewer than 3 vertices.
Result<TriangleMesh, std::string> read_ply_mesh(const std::string& path);

}  // namespace scancrew::io
