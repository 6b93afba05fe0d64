#pragma once

// Tiny triangle meshes for the sim tests.

#include <algorithm>

#include "sim/mesh_io.hpp"

namespace scancrew::sim::test {

// The unit cube [0, 1]^3 moved by `at`, as 12 triangles wound outward (inward when
// flipped); without its top face when open.
inline TriangleMesh cube(bool flipped = false, bool open = false, msg::Vec3 at = {0, 0, 0}) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({at.x + (i & 1), at.y + ((i >> 1) & 1), at.z + (i >> 2)});
  m.triangles = {{0, 2, 1}, {1, 2, 3},   // bottom, -z
                 {0, 1, 4}, {1, 5, 4},   // -y
                 {2, 6, 3}, {3, 6, 7},   // +y
                 {0, 4, 2}, {2, 4, 6},   // -x
                 {1, 3, 5}, {3, 7, 5}};  // +x
  if (!open) {
    m.triangles.push_back({4, 5, 6});  // top, +z
    m.triangles.push_back({5, 7, 6});
  }
  if (flipped)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

}  // namespace scancrew::sim::test
