#include "core/io/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>

#include "core/vec3_math.hpp"

namespace scancrew::io {

msg::Vec3 TriangleMesh::min() const {
  if (vertices.empty()) return {};
  msg::Vec3 m = vertices.front();
  for (const auto& v : vertices) m = {std::min(m.x, v.x), std::min(m.y, v.y), std::min(m.z, v.z)};
  return m;
}

msg::Vec3 TriangleMesh::max() const {
  if (vertices.empty()) return {};
  msg::Vec3 m = vertices.front();
  for (const auto& v : vertices) m = {std::max(m.x, v.x), std::max(m.y, v.y), std::max(m.z, v.z)};
  return m;
}

double TriangleMesh::area() const {
  double a = 0;
  for (const auto& t : triangles)
    a += 0.5 * vec3::norm(vec3::cross(vec3::sub(vertices[t[1]], vertices[t[0]]),
                                      vec3::sub(vertices[t[2]], vertices[t[0]])));
  return a;
}

}  // namespace scancrew::io
