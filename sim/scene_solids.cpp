#include "sim/scene_solids.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/vec3_math.hpp"

namespace scancrew::sim {

namespace {

using msg::Vec3;
using vec3::sub;

constexpr double kGridCellM = 2.0;          // x-y grid of boxes and cylinders
constexpr int64_t kMaxGridCells = 1 << 20;  // the cell grows beyond this
constexpr int64_t kMaxCellsPerSolid = 256;  // a solid over more is tested always
constexpr double kTinyDir = 1e-12;          // below this a direction component is 0

// Shrinks (t0, t1) to the part where lo < p + t d < hi; false when it becomes empty.
bool clip_slab(double p, double d, double lo, double hi, double* t0, double* t1) {
  if (std::abs(d) < kTinyDir) return p > lo && p < hi;
  double ta = (lo - p) / d, tb = (hi - p) / d;
  if (ta > tb) std::swap(ta, tb);
  *t0 = std::max(*t0, ta);
  *t1 = std::min(*t1, tb);
  return *t0 < *t1;
}

// Box-local coordinates of a world-frame offset (turned by -yaw).
Vec3 to_local(const Solid& s, const Vec3& d) {
  return {d.x * s.cos_yaw + d.y * s.sin_yaw, -d.x * s.sin_yaw + d.y * s.cos_yaw, d.z};
}

// Whether the triangle overlaps the upright cylinder: clip it to the slab z in [z0, z1]
// (Sutherland-Hodgman), then whether (x, y) lies within r of the clipped polygon in x-y.
bool triangle_overlaps_cylinder(const Vec3& a, const Vec3& b, const Vec3& c, double x, double y,
                                double r, double z0, double z1) {
  Vec3 poly[8] = {a, b, c}, next[8];
  int n = 3;
  for (const auto& [level, keep_above] : {std::pair{z0, true}, std::pair{z1, false}}) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const Vec3 &p = poly[i], &q = poly[(i + 1) % n];
      const bool p_in = keep_above ? p.z >= level : p.z <= level;
      const bool q_in = keep_above ? q.z >= level : q.z <= level;
      if (p_in) next[m++] = p;
      if (p_in != q_in) next[m++] = vec3::add_scaled(p, sub(q, p), (level - p.z) / (q.z - p.z));
    }
    n = m;
    if (n == 0) return false;
    std::copy(next, next + n, poly);
  }
  // inside the (convex) projected polygon: the point is on one side of every edge
  bool pos = false, neg = false;
  const double r2 = r * r;
  for (int i = 0; i < n; ++i) {
    const Vec3 &p = poly[i], &q = poly[(i + 1) % n];
    const double ex = q.x - p.x, ey = q.y - p.y, px = x - p.x, py = y - p.y;
    const double side = ex * py - ey * px;
    pos = pos || side > 0;
    neg = neg || side < 0;
    const double len2 = ex * ex + ey * ey;
    const double t = len2 > 0 ? std::clamp((px * ex + py * ey) / len2, 0.0, 1.0) : 0.0;
    const double dx = px - t * ex, dy = py - t * ey;
    if (dx * dx + dy * dy < r2) return true;
  }
  return !(pos && neg);
}

}  // namespace

void Aabb::add(const Vec3& p) {
  lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
  hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
}

bool Aabb::overlaps(const Aabb& o, double tol) const {
  return lo.x <= o.hi.x + tol && o.lo.x <= hi.x + tol && lo.y <= o.hi.y + tol &&
         o.lo.y <= hi.y + tol && lo.z <= o.hi.z + tol && o.lo.z <= hi.z + tol;
}

bool Solid::contains(const Vec3& p, double eps) const {
  const Vec3 d = sub(p, center);
  switch (kind) {
    case Kind::kBox: {
      const double lx = d.x * cos_yaw + d.y * sin_yaw, ly = -d.x * sin_yaw + d.y * cos_yaw;
      return std::abs(lx) < half.x + eps && std::abs(ly) < half.y + eps &&
             std::abs(d.z) < half.z + eps;
    }
    case Kind::kCylinder: {
      const double r = half.x + eps;
      return std::abs(d.z) < half.z + eps && d.x * d.x + d.y * d.y < r * r;
    }
    case Kind::kBelowFloor:
      return p.z < eps;
  }
  return false;
}

bool Solid::crossed_by(const Vec3& a, const Vec3& b, double t0, double t1) const {
  const Vec3 d = sub(b, a);
  switch (kind) {
    case Kind::kBox: {
      const Vec3 p = to_local(*this, sub(a, center)), dl = to_local(*this, d);
      return clip_slab(p.x, dl.x, -half.x, half.x, &t0, &t1) &&
             clip_slab(p.y, dl.y, -half.y, half.y, &t0, &t1) &&
             clip_slab(p.z, dl.z, -half.z, half.z, &t0, &t1);
    }
    case Kind::kCylinder: {
      const Vec3 p = sub(a, center);
      if (!clip_slab(p.z, d.z, -half.z, half.z, &t0, &t1)) return false;
      // |p_xy + t d_xy|² < r²: between the roots of a t² + 2 h t + c
      const double qa = d.x * d.x + d.y * d.y, h = p.x * d.x + p.y * d.y,
                   qc = p.x * p.x + p.y * p.y - half.x * half.x;
      if (qa < kTinyDir * kTinyDir) return qc < 0;
      const double disc = h * h - qa * qc;
      if (disc <= 0) return false;
      const double root = std::sqrt(disc);
      return std::max(t0, (-h - root) / qa) < std::min(t1, (-h + root) / qa);
    }
    case Kind::kBelowFloor:
      return a.z + t0 * d.z < 0 || a.z + t1 * d.z < 0;
  }
  return false;
}

bool Solid::overlaps_cylinder(double x, double y, double radius_m, double z0_m, double z1_m) const {
  switch (kind) {
    case Kind::kBox: {
      if (z1_m <= center.z - half.z || z0_m >= center.z + half.z) return false;
      const Vec3 p = to_local(*this, {x - center.x, y - center.y, 0});
      const double dx = p.x - std::clamp(p.x, -half.x, half.x);
      const double dy = p.y - std::clamp(p.y, -half.y, half.y);
      return dx * dx + dy * dy < radius_m * radius_m;
    }
    case Kind::kCylinder: {
      if (z1_m <= center.z - half.z || z0_m >= center.z + half.z) return false;
      const double dx = x - center.x, dy = y - center.y, r = radius_m + half.x;
      return dx * dx + dy * dy < r * r;
    }
    case Kind::kBelowFloor:
      return z0_m < 0;
  }
  return false;
}

bool Solid::overlaps_sphere(const Vec3& c, double radius_m) const {
  const Vec3 d = sub(c, center);
  switch (kind) {
    case Kind::kBox: {
      const Vec3 p = to_local(*this, d);
      const Vec3 q{std::clamp(p.x, -half.x, half.x), std::clamp(p.y, -half.y, half.y),
                   std::clamp(p.z, -half.z, half.z)};
      return vec3::distance2(p, q) < radius_m * radius_m;
    }
    case Kind::kCylinder: {
      const double dz = d.z - std::clamp(d.z, -half.z, half.z);
      const double rho = std::sqrt(d.x * d.x + d.y * d.y);
      const double dr = std::max(0.0, rho - half.x);
      return dz * dz + dr * dr < radius_m * radius_m;
    }
    case Kind::kBelowFloor:
      return c.z - radius_m < 0;
  }
  return false;
}

Solid make_box_solid(const Vec3& center, const Vec3& half, double yaw_rad) {
  Solid s{.kind = Solid::Kind::kBox,
          .center = center,
          .half = half,
          .cos_yaw = std::cos(yaw_rad),
          .sin_yaw = std::sin(yaw_rad)};
  for (int i = 0; i < 8; ++i) {
    const double lx = (i & 1) != 0 ? half.x : -half.x, ly = (i & 2) != 0 ? half.y : -half.y,
                 lz = (i & 4) != 0 ? half.z : -half.z;
    s.box.add({center.x + lx * s.cos_yaw - ly * s.sin_yaw,
               center.y + lx * s.sin_yaw + ly * s.cos_yaw, center.z + lz});
  }
  return s;
}

Solid make_cylinder_solid(const Vec3& center, double radius_m, double height_m) {
  const double hh = 0.5 * height_m, r = radius_m;
  Solid s{.kind = Solid::Kind::kCylinder, .center = center, .half = {r, r, hh}};
  s.box.add({center.x - r, center.y - r, center.z - hh});
  s.box.add({center.x + r, center.y + r, center.z + hh});
  return s;
}

SceneSolids::SceneSolids(const SceneSpec& sc, const std::vector<TriangleMesh>& placed_meshes) {
  // floor, ceiling and walls as build_mjcf() places them
  const Vec3 lo = sc.min_m, hi = sc.max_m;
  const double sx = hi.x - lo.x, sy = hi.y - lo.y, cx = 0.5 * (lo.x + hi.x),
               cy = 0.5 * (lo.y + hi.y);
  Solid floor{.kind = Solid::Kind::kBelowFloor};
  floor.box.add({-Aabb::kBig, -Aabb::kBig, -Aabb::kBig});
  floor.box.add({Aabb::kBig, Aabb::kBig, 0});
  solids_.push_back(floor);
  if (sc.ceiling) {
    ceiling_ = static_cast<int>(solids_.size());
    solids_.push_back(
        make_box_solid({cx, cy, hi.z + 0.05}, {0.5 * sx + 0.2, 0.5 * sy + 0.2, 0.05}, 0));
  }
  if (sc.wall_height_m > 0) {
    const double t = sc.wall_thickness_m, h = sc.wall_height_m;
    const Vec3 centers[4] = {{cx, hi.y + 0.5 * t, 0},
                             {cx, lo.y - 0.5 * t, 0},
                             {hi.x + 0.5 * t, cy, 0},
                             {lo.x - 0.5 * t, cy, 0}};
    const Vec3 halves[4] = {{0.5 * sx + t, 0.5 * t, 0},
                            {0.5 * sx + t, 0.5 * t, 0},
                            {0.5 * t, 0.5 * sy, 0},
                            {0.5 * t, 0.5 * sy, 0}};
    for (int k = 0; k < 4; ++k) {
      walls_[static_cast<size_t>(k)] = static_cast<int>(solids_.size());
      solids_.push_back(make_box_solid(vec3::add(centers[k], {0, 0, 0.5 * h}),
                                       vec3::add(halves[k], {0, 0, 0.5 * h}), 0));
    }
  }
  for (uint32_t i = 0; i < solids_.size(); ++i) always_.push_back(i);
  first_box_ = static_cast<int>(solids_.size());
  for (const BoxSpec& b : sc.boxes)
    solids_.push_back(make_box_solid(b.center_m, vec3::add_scaled({}, b.size_m, 0.5), b.yaw_rad));
  first_cylinder_ = static_cast<int>(solids_.size());
  for (const CylinderSpec& c : sc.cylinders)
    solids_.push_back(make_cylinder_solid(c.center_m, c.radius_m, c.height_m));

  // the x-y grid over the boxes and cylinders
  const auto first = static_cast<size_t>(first_box_);
  if (first < solids_.size()) {
    Aabb all;
    for (size_t i = first; i < solids_.size(); ++i) {
      all.add(solids_[i].box.lo);
      all.add(solids_[i].box.hi);
    }
    grid_x0_ = all.lo.x;
    grid_y0_ = all.lo.y;
    const double ex = all.hi.x - all.lo.x, ey = all.hi.y - all.lo.y;
    grid_cell_m_ = std::max(kGridCellM, std::sqrt(ex * ey / static_cast<double>(kMaxGridCells)));
    grid_nx_ = static_cast<int>(std::floor(ex / grid_cell_m_)) + 1;
    grid_ny_ = static_cast<int>(std::floor(ey / grid_cell_m_)) + 1;
    const auto cells = static_cast<size_t>(grid_nx_) * static_cast<size_t>(grid_ny_);
    std::vector<std::vector<uint32_t>> lists(cells);
    for (size_t i = first; i < solids_.size(); ++i) {
      const Aabb& b = solids_[i].box;
      const int i0 = static_cast<int>(std::floor((b.lo.x - grid_x0_) / grid_cell_m_));
      const int i1 = std::min(grid_nx_ - 1, static_cast<int>((b.hi.x - grid_x0_) / grid_cell_m_));
      const int j0 = static_cast<int>(std::floor((b.lo.y - grid_y0_) / grid_cell_m_));
      const int j1 = std::min(grid_ny_ - 1, static_cast<int>((b.hi.y - grid_y0_) / grid_cell_m_));
      if (int64_t{i1 - i0 + 1} * (j1 - j0 + 1) > kMaxCellsPerSolid) {
        always_.push_back(static_cast<uint32_t>(i));
        continue;
      }
      for (int j = std::max(j0, 0); j <= j1; ++j)
        for (int k = std::max(i0, 0); k <= i1; ++k)
          lists[static_cast<size_t>(j) * static_cast<size_t>(grid_nx_) + static_cast<size_t>(k)]
              .push_back(static_cast<uint32_t>(i));
    }
    grid_offsets_.assign(cells + 1, 0);
    for (size_t c = 0; c < cells; ++c) {
      grid_offsets_[c + 1] = grid_offsets_[c] + static_cast<uint32_t>(lists[c].size());
      grid_entries_.insert(grid_entries_.end(), lists[c].begin(), lists[c].end());
    }
  }
  if (!placed_meshes.empty()) {
    meshes_ = std::make_unique<MeshOcclusion>(placed_meshes, 0);
    if (meshes_->empty()) meshes_.reset();
  }
}

SceneSolids::SceneSolids(SceneSolids&&) noexcept = default;
SceneSolids& SceneSolids::operator=(SceneSolids&&) noexcept = default;
SceneSolids::~SceneSolids() = default;

size_t SceneSolids::triangle_count() const {
  return meshes_ ? meshes_->triangle_count() : 0;
}

// Calls f(solid) for the grid's solids listed in the cells that [x0, x1] x [y0, y1]
// overlaps (a solid over several cells may come more than once), until f returns true.
template <class F>
bool SceneSolids::any_grid_solid(double x0, double y0, double x1, double y1, F&& f) const {
  if (grid_nx_ == 0) return false;
  const int i0 = std::max(0, static_cast<int>(std::floor((x0 - grid_x0_) / grid_cell_m_)));
  const int i1 =
      std::min(grid_nx_ - 1, static_cast<int>(std::floor((x1 - grid_x0_) / grid_cell_m_)));
  const int j0 = std::max(0, static_cast<int>(std::floor((y0 - grid_y0_) / grid_cell_m_)));
  const int j1 =
      std::min(grid_ny_ - 1, static_cast<int>(std::floor((y1 - grid_y0_) / grid_cell_m_)));
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const size_t c =
          static_cast<size_t>(j) * static_cast<size_t>(grid_nx_) + static_cast<size_t>(i);
      for (uint32_t e = grid_offsets_[c]; e < grid_offsets_[c + 1]; ++e)
        if (f(solids_[grid_entries_[e]])) return true;
    }
  return false;
}

bool SceneSolids::segment_blocked(const Vec3& a, const Vec3& b, double end_margin_m) const {
  const Vec3 d = sub(b, a);
  const double length = std::sqrt(vec3::dot(d, d));
  if (!(length > 2 * end_margin_m)) return false;
  const double t0 = end_margin_m / length, t1 = 1 - t0;
  for (const uint32_t i : always_)
    if (solids_[i].crossed_by(a, b, t0, t1)) return true;
  if (grid_nx_ > 0) {
    // the cells along the segment, one x-y cell row at a time (rows are at most a few long)
    const Vec3 p = vec3::add_scaled(a, d, t0), q = vec3::add_scaled(a, d, t1);
    const int j0 = static_cast<int>(std::floor((std::min(p.y, q.y) - grid_y0_) / grid_cell_m_));
    const int j1 = static_cast<int>(std::floor((std::max(p.y, q.y) - grid_y0_) / grid_cell_m_));
    for (int j = std::max(j0, 0); j <= std::min(j1, grid_ny_ - 1); ++j) {
      // the part of the segment in this row: its x extent
      double s0 = t0, s1 = t1;
      const double ylo = grid_y0_ + j * grid_cell_m_;
      if (std::abs(d.y) >= kTinyDir) {
        double ta = (ylo - a.y) / d.y, tb = (ylo + grid_cell_m_ - a.y) / d.y;
        if (ta > tb) std::swap(ta, tb);
        s0 = std::max(s0, ta);
        s1 = std::min(s1, tb);
        if (s0 > s1) continue;
      }
      const double xa = a.x + s0 * d.x, xb = a.x + s1 * d.x;
      const double y = ylo + 0.5 * grid_cell_m_;
      const auto hit = [&](const Solid& s) { return s.crossed_by(a, b, t0, t1); };
      if (any_grid_solid(std::min(xa, xb), y, std::max(xa, xb), y, hit)) return true;
    }
  }
  return meshes_ && meshes_->blocked(a, d, t0, t1);
}

bool SceneSolids::cylinder_overlaps(double x, double y, double radius_m, double z0_m,
                                    double z1_m) const {
  const auto hit = [&](const Solid& s) { return s.overlaps_cylinder(x, y, radius_m, z0_m, z1_m); };
  for (const uint32_t i : always_)
    if (hit(solids_[i])) return true;
  if (any_grid_solid(x - radius_m, y - radius_m, x + radius_m, y + radius_m, hit)) return true;
  if (!meshes_) return false;
  return meshes_->any_triangle_near(
      {x - radius_m, y - radius_m, z0_m}, {x + radius_m, y + radius_m, z1_m},
      [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        return triangle_overlaps_cylinder(a, b, c, x, y, radius_m, z0_m, z1_m);
      });
}

bool SceneSolids::sphere_overlaps(const Vec3& center, double radius_m) const {
  const auto hit = [&](const Solid& s) { return s.overlaps_sphere(center, radius_m); };
  for (const uint32_t i : always_)
    if (hit(solids_[i])) return true;
  if (any_grid_solid(center.x - radius_m, center.y - radius_m, center.x + radius_m,
                     center.y + radius_m, hit))
    return true;
  if (!meshes_) return false;
  const Vec3 r{radius_m, radius_m, radius_m};
  return meshes_->any_triangle_near(
      sub(center, r), vec3::add(center, r), [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        return vec3::distance2(center, vec3::closest_point_on_triangle(center, a, b, c)) <
               radius_m * radius_m;
      });
}

}  // namespace scancrew::sim
