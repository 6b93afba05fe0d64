#pragma once

// Triangle meshes from PLY files (Turk, "The PLY polygon file format", 1994), as written by
// reconstruction pipelines (Open3D, voxblox, nvblox, CloudCompare, MeshLab). Read here rather
// than with assimp (sim/mesh_io.hpp), which merges vertices, drops degenerate faces and
// refuses flat meshes: an evaluation must score the mesh exactly as written.
//
// Read: format ascii, binary_little_endian or binary_big_endian; element "vertex" with
// scalar properties x, y, z of any type (other properties — normals, colours — skipped);
// element "face" with a list property "vertex_indices" (or "vertex_index") of any count and
// index types, polygons split into triangle fans; any other element skipped. A "face"
// element of 0 faces gives an empty mesh.

#include <string>

#include "executors/result.hpp"
#include "sim/mesh_io.hpp"

namespace scancrew::eval {

// Errors name the file and the cause: a missing file, not a PLY, an unsupported format or
// property type, no x/y/z, no face element (a point cloud), data that ends early (which
// element and which item), a vertex index out of range, a face of fewer than 3 vertices.
Result<sim::TriangleMesh, std::string> read_ply_mesh(const std::string& path);

}  // namespace scancrew::eval
