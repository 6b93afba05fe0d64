#pragma once

// Which surface points of a scene can be seen from outside its meshes: the thesis scores a
// reconstruction against the ground-truth mesh with "all the invisible surfaces pruned
// beforehand (e.g. the interior floor and walls)" (2.6.2). A triangle soup is not a solid, so
// sim::sample_surfaces cannot tell a wall's outer face from the partitions and floors closed
// inside a building; this class tells them apart by casting rays.
//
// A point is exposed when at least one ray from it, among the point's normal, its reverse
// and `rays` directions spread evenly over the sphere (a Fibonacci lattice), leaves the
// meshes' bounding box without crossing a mesh triangle or going under the floor (z = 0).
// Both sides of a triangle block, and rays are cast on both sides of the point's surface,
// so a mesh whose winding points inward is judged as one that points outward. A point
// outside the meshes' bounding box is exposed.
//
// Limits: what blocks is the meshes and the floor only (boxes, cylinders and walls are
// handled by sample_surfaces' solid test); a point seen only through a gap that none of
// the directions passes counts as hidden (more rays, finer lattice).
//
// Thread safety: const member functions may be called from several threads at once.

#include <array>
#include <cstdint>
#include <vector>

#include "interfaces/geometry.hpp"
#include "sim/mesh_io.hpp"

namespace scancrew::sim {

class MeshOcclusion {
 public:
  // Copies the triangles of every mesh and builds a bounding-volume hierarchy over them
  // (median split on the longest axis, up to 4 triangles a leaf). Degenerate triangles are
  // left out.
  MeshOcclusion(const std::vector<TriangleMesh>& meshes, int rays);

  bool empty() const { return triangles_.empty(); }
  size_t triangle_count() const { return triangles_.size(); }

  // Whether p (with unit normal n) is seen from outside the meshes (class comment).
  bool exposed(const msg::Vec3& p, const msg::Vec3& n) const;

  // Whether the segment origin + t dir, t in [t_min, t_max], crosses a triangle.
  bool blocked(const msg::Vec3& origin, const msg::Vec3& dir, double t_min, double t_max) const;

  // Calls f(v0, v1, v2) for the triangles in the hierarchy's leaves whose boxes overlap
  // [lo, hi] (a superset of the triangles that do), until f returns true; returns whether
  // one did. Allocates nothing.
  template <class F>
  bool any_triangle_near(const msg::Vec3& lo, const msg::Vec3& hi, F&& f) const;

 private:
  struct Triangle {
    msg::Vec3 v0, e1, e2;  // v1 = v0 + e1, v2 = v0 + e2
  };
  struct Node {
    msg::Vec3 lo, hi;
    uint32_t first = 0, count = 0;  // leaf: triangles [first, first + count); inner: count 0
    uint32_t right = 0;             // inner: the left child is the next node
  };

  uint32_t build(uint32_t first, uint32_t count, std::vector<msg::Vec3>& centroids);
  bool escapes(const msg::Vec3& origin, const msg::Vec3& dir) const;

  std::vector<Triangle> triangles_;
  std::vector<Node> nodes_;
  std::vector<msg::Vec3> directions_;
  msg::Vec3 lo_, hi_;  // the triangles' bounding box, grown by kMargin
};

template <class F>
bool MeshOcclusion::any_triangle_near(const msg::Vec3& lo, const msg::Vec3& hi, F&& f) const {
  if (nodes_.empty()) return false;
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const uint32_t self = stack[--top];
    const Node& node = nodes_[self];
    if (node.lo.x > hi.x || node.lo.y > hi.y || node.lo.z > hi.z || lo.x > node.hi.x ||
        lo.y > node.hi.y || lo.z > node.hi.z)
      continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const Triangle& t = triangles_[i];
        const msg::Vec3 v1{t.v0.x + t.e1.x, t.v0.y + t.e1.y, t.v0.z + t.e1.z};
        const msg::Vec3 v2{t.v0.x + t.e2.x, t.v0.y + t.e2.y, t.v0.z + t.e2.z};
        if (f(t.v0, v1, v2)) return true;
      }
      continue;
    }
    if (top + 2 > 64) return true;  // cannot happen with a median split (see blocked())
    stack[top++] = node.right;
    stack[top++] = self + 1;  // the left child is the next node
  }
  return false;
}

}  // namespace scancrew::sim
