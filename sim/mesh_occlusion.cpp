#include "sim/mesh_occlusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

namespace scancrew::sim {

namespace {

using msg::Vec3;

constexpr double kMargin = 0.01;    // m, the bounding box is grown by this
constexpr double kRayStart = 1e-3;  // m, a ray starts this far from its point (no self-hit)
constexpr double kTinyDir = 1e-30;  // a zero direction component becomes this (no 0 * inf)
constexpr uint32_t kLeafSize = 4;   // triangles a leaf holds at most
constexpr int kMaxDepth = 64;       // traversal stack (a median split halves each level)

Vec3 sub(const Vec3& a, const Vec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
double axis(const Vec3& v, int a) {
  return a == 0 ? v.x : (a == 1 ? v.y : v.z);
}
Vec3 vmin(const Vec3& a, const Vec3& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
Vec3 vmax(const Vec3& a, const Vec3& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}

// Fibonacci lattice: n directions spread evenly over the unit sphere (González 2010).
std::vector<Vec3> sphere_directions(int n) {
  std::vector<Vec3> dirs;
  dirs.reserve(static_cast<size_t>(std::max(n, 0)));
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * i;
    dirs.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  return dirs;
}

// The slab test: whether origin + t dir enters [lo, hi] for some t in [t_min, t_max].
bool hits_box(const Vec3& lo, const Vec3& hi, const Vec3& origin, const Vec3& inv, double t_min,
              double t_max) {
  for (int a = 0; a < 3; ++a) {
    double t0 = (axis(lo, a) - axis(origin, a)) * axis(inv, a);
    double t1 = (axis(hi, a) - axis(origin, a)) * axis(inv, a);
    if (t0 > t1) std::swap(t0, t1);
    t_min = std::max(t_min, t0);
    t_max = std::min(t_max, t1);
    if (t_min > t_max) return false;
  }
  return true;
}

}  // namespace

MeshOcclusion::MeshOcclusion(const std::vector<TriangleMesh>& meshes, int rays)
    : directions_(sphere_directions(rays)) {
  for (const TriangleMesh& m : meshes)
    for (const auto& t : m.triangles) {
      const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
      const Triangle tri{a, sub(b, a), sub(c, a)};
      const Vec3 n = cross(tri.e1, tri.e2);
      if (dot(n, n) > 0) triangles_.push_back(tri);
    }
  if (triangles_.empty()) return;
  std::vector<Vec3> centroids(triangles_.size());
  lo_ = triangles_[0].v0;
  hi_ = lo_;
  for (size_t i = 0; i < triangles_.size(); ++i) {
    const Triangle& t = triangles_[i];
    const Vec3 b{t.v0.x + t.e1.x, t.v0.y + t.e1.y, t.v0.z + t.e1.z};
    const Vec3 c{t.v0.x + t.e2.x, t.v0.y + t.e2.y, t.v0.z + t.e2.z};
    centroids[i] = {(t.v0.x + b.x + c.x) / 3, (t.v0.y + b.y + c.y) / 3, (t.v0.z + b.z + c.z) / 3};
    lo_ = vmin(lo_, vmin(t.v0, vmin(b, c)));
    hi_ = vmax(hi_, vmax(t.v0, vmax(b, c)));
  }
  lo_ = sub(lo_, {kMargin, kMargin, kMargin});
  hi_ = {hi_.x + kMargin, hi_.y + kMargin, hi_.z + kMargin};
  nodes_.reserve(2 * triangles_.size() / kLeafSize + 1);
  build(0, static_cast<uint32_t>(triangles_.size()), centroids);
}

// Builds the subtree over triangles_[first, first + count) and returns its node's index;
// reorders the triangles (and their centroids) in place.
uint32_t MeshOcclusion::build(uint32_t first, uint32_t count, std::vector<Vec3>& centroids) {
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back({});
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  Vec3 hi{-lo.x, -lo.y, -lo.z};
  Vec3 clo = lo, chi = hi;  // the centroids' box: where to split
  for (uint32_t i = first; i < first + count; ++i) {
    const Triangle& t = triangles_[i];
    const Vec3 b{t.v0.x + t.e1.x, t.v0.y + t.e1.y, t.v0.z + t.e1.z};
    const Vec3 c{t.v0.x + t.e2.x, t.v0.y + t.e2.y, t.v0.z + t.e2.z};
    lo = vmin(lo, vmin(t.v0, vmin(b, c)));
    hi = vmax(hi, vmax(t.v0, vmax(b, c)));
    clo = vmin(clo, centroids[i]);
    chi = vmax(chi, centroids[i]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  const Vec3 extent = sub(chi, clo);
  const int split =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  if (count <= kLeafSize || axis(extent, split) <= 0) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  // median split: sort an index range by centroid, then apply the order to both arrays
  const uint32_t half = count / 2;
  std::vector<uint32_t> order(count);
  std::iota(order.begin(), order.end(), first);
  std::nth_element(order.begin(), order.begin() + half, order.end(), [&](uint32_t a, uint32_t b) {
    return axis(centroids[a], split) < axis(centroids[b], split);
  });
  std::vector<Triangle> tris(count);
  std::vector<Vec3> cents(count);
  for (uint32_t i = 0; i < count; ++i) {
    tris[i] = triangles_[order[i]];
    cents[i] = centroids[order[i]];
  }
  std::copy(tris.begin(), tris.end(), triangles_.begin() + first);
  std::copy(cents.begin(), cents.end(), centroids.begin() + first);
  build(first, half, centroids);
  const uint32_t right = build(first + half, count - half, centroids);
  nodes_[index].right = right;
  return index;
}

bool MeshOcclusion::blocked(const Vec3& origin, const Vec3& dir, double t_min, double t_max) const {
  if (triangles_.empty()) return false;
  const auto safe = [](double d) { return d == 0 ? kTinyDir : d; };
  const Vec3 inv{1.0 / safe(dir.x), 1.0 / safe(dir.y), 1.0 / safe(dir.z)};
  uint32_t stack[kMaxDepth];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!hits_box(node.lo, node.hi, origin, inv, t_min, t_max)) continue;
    if (node.count > 0) {
      // Möller & Trumbore (1997), both faces
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const Triangle& t = triangles_[i];
        const Vec3 p = cross(dir, t.e2);
        const double det = dot(t.e1, p);
        if (std::abs(det) < 1e-15) continue;  // parallel to the triangle's plane
        const double inv_det = 1.0 / det;
        const Vec3 s = sub(origin, t.v0);
        const double u = dot(s, p) * inv_det;
        if (u < 0 || u > 1) continue;
        const Vec3 q = cross(s, t.e1);
        const double v = dot(dir, q) * inv_det;
        if (v < 0 || u + v > 1) continue;
        const double t_hit = dot(t.e2, q) * inv_det;
        if (t_hit >= t_min && t_hit <= t_max) return true;
      }
      continue;
    }
    // inner: the left child is the next node
    const uint32_t self = static_cast<uint32_t>(&node - nodes_.data());
    if (top + 2 > kMaxDepth) return true;  // cannot happen with a median split; be safe
    stack[top++] = node.right;
    stack[top++] = self + 1;
  }
  return false;
}

// Whether the ray from origin along dir (unit) leaves the bounding box above the floor
// without crossing a triangle.
bool MeshOcclusion::escapes(const Vec3& origin, const Vec3& dir) const {
  double t_exit = std::numeric_limits<double>::max();
  for (int a = 0; a < 3; ++a) {
    const double d = axis(dir, a);
    if (d > 0) t_exit = std::min(t_exit, (axis(hi_, a) - axis(origin, a)) / d);
    if (d < 0) t_exit = std::min(t_exit, (axis(lo_, a) - axis(origin, a)) / d);
  }
  if (dir.z < 0 && -origin.z / dir.z <= t_exit) return false;  // the floor comes first
  return !blocked(origin, dir, kRayStart, t_exit);
}

bool MeshOcclusion::exposed(const Vec3& p, const Vec3& n) const {
  if (triangles_.empty()) return true;
  if (p.x < lo_.x || p.y < lo_.y || p.z < lo_.z || p.x > hi_.x || p.y > hi_.y || p.z > hi_.z)
    return true;
  if (escapes(p, n) || escapes(p, {-n.x, -n.y, -n.z})) return true;
  return std::any_of(directions_.begin(), directions_.end(),
                     [&](const Vec3& d) { return escapes(p, d); });
}

}  // namespace scancrew::sim
