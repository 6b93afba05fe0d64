#include "core/io/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace scancrew::io {

namespace {

msg::Vec3 sub(const msg::Vec3& a, const msg::Vec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
msg::Vec3 cross(const msg::Vec3& a, const msg::Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double norm(const msg::Vec3& a) {
  return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
}

}  // namespace

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
    a +=
        0.5 * norm(cross(sub(vertices[t[1]], vertices[t[0]]), sub(vertices[t[2]], vertices[t[0]])));
  return a;
}

}  // namespace scancrew::io
