#pragma once

// TriangleMesh: vertices and index triangles, in double precision: a scene's mesh as the
// simulator loads it (sim/mesh_io.hpp) and a reconstruction as the evaluation reads it
// (core/io/ply.hpp).

#include <array>
#include <cstdint>
#include <vector>

#include "interfaces/geometry.hpp"

namespace scancrew::io {

struct TriangleMesh {
  std::vector<msg::Vec3> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;  // indices into vertices

  msg::Vec3 min() const;  // bounding box; (0,0,0) when empty
  msg::Vec3 max() const;
  double area() const;
};

}  // namespace scancrew::io
