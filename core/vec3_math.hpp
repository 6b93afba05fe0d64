#pragma once

// Small vector helpers on msg::Vec3 and the closest point of a segment or a triangle to a
// point (Ericson, "Real-Time Collision Detection", 2005, 5.1.2 and 5.1.5). Inline: they sit
// on hot paths (the reconstruction error's nearest triangle, body clearance tests).

#include <algorithm>
#include <cmath>

#include "interfaces/geometry.hpp"

namespace scancrew::vec3 {

using msg::Vec3;

inline Vec3 add(const Vec3& a, const Vec3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 sub(const Vec3& a, const Vec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 add_scaled(const Vec3& a, const Vec3& d, double s) {
  return {a.x + s * d.x, a.y + s * d.y, a.z + s * d.z};
}
inline double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) {
  return std::sqrt(dot(a, a));
}
inline double distance2(const Vec3& a, const Vec3& b) {
  const Vec3 d = sub(a, b);
  return dot(d, d);
}

inline Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = sub(b, a);
  const double len2 = dot(ab, ab);
  if (!(len2 > 0)) return a;
  return add_scaled(a, ab, std::clamp(dot(sub(p, a), ab) / len2, 0.0, 1.0));
}

// The point of the triangle (a, b, c) closest to p; exact up to rounding, also for a
// degenerate triangle (a segment or a point). Ericson 5.1.5: find the Voronoi region of the
// triangle (vertex, edge or face) holding p from dot products only, then project onto it.
inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return add_scaled(a, ab, d1 / (d1 - d3));
  const Vec3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return add_scaled(a, ac, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return add_scaled(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double area2 = va + vb + vc;  // |ab × ac|²
  if (!(area2 > 0)) {
    // a degenerate triangle (rounding put p in no region): its nearest edge
    Vec3 best = closest_point_on_segment(p, a, b);
    for (const Vec3& q : {closest_point_on_segment(p, b, c), closest_point_on_segment(p, c, a)})
      if (distance2(p, q) < distance2(p, best)) best = q;
    return best;
  }
  return add_scaled(add_scaled(a, ab, vb / area2), ac, vc / area2);
}

}  // namespace scancrew::vec3
