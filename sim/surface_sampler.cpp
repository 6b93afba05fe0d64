#include "sim/surface_sampler.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <sstream>

#include "sim/mesh_occlusion.hpp"
#include "sim/scene_solids.hpp"

namespace scancrew::sim {

namespace {

using msg::Vec3;

Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
Vec3 operator-(const Vec3& a, const Vec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
Vec3 operator*(double s, const Vec3& a) {
  return {s * a.x, s * a.y, s * a.z};
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double norm(const Vec3& a) {
  return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
}

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// A surface sampled as one: a parallelogram, a horizontal disk, a cylinder's side, or a
// whole mesh (one draw of the count per triangle).
struct Surface {
  enum class Kind { kRect, kDisk, kCylinderSide, kMesh } kind = Kind::kRect;
  int owner = -1;                 // index of the solid it bounds (not tested against it); -1: none
  Vec3 origin, u, v, normal;      // rect: origin + s u + t v; disk/side: origin is the centre
  double radius = 0, height = 0;  // disk, side (side: origin is the bottom centre)
  const TriangleMesh* mesh = nullptr;
  double area = 0;
  Aabb box;
};

Surface make_rect(const Vec3& origin, const Vec3& u, const Vec3& v, const Vec3& normal, int owner) {
  Surface s{.kind = Surface::Kind::kRect,
            .owner = owner,
            .origin = origin,
            .u = u,
            .v = v,
            .normal = normal,
            .area = norm(cross(u, v))};
  for (const Vec3& p : {origin, origin + u, origin + v, origin + u + v}) s.box.add(p);
  return s;
}

Surface make_disk(const Vec3& center, double radius, double nz, int owner) {
  Surface s{.kind = Surface::Kind::kDisk,
            .owner = owner,
            .origin = center,
            .normal = {0, 0, nz},
            .radius = radius,
            .area = std::numbers::pi * radius * radius};
  s.box.add(center - Vec3{radius, radius, 0});
  s.box.add(center + Vec3{radius, radius, 0});
  return s;
}

double mesh_triangle_area(const TriangleMesh& m, const std::array<uint32_t, 3>& t) {
  return 0.5 *
         norm(cross(m.vertices[t[1]] - m.vertices[t[0]], m.vertices[t[2]] - m.vertices[t[0]]));
}

// The scene's surfaces facing the bounds, each owned by the solid it bounds: the floor, the
// ceiling's underside, the walls' inner faces, the boxes' and cylinders' faces.
std::vector<Surface> room_and_solid_surfaces(const SceneSpec& sc, const SceneSolids& solids) {
  std::vector<Surface> out;
  const Vec3 lo = sc.min_m, hi = sc.max_m;
  const double sx = hi.x - lo.x, sy = hi.y - lo.y;
  out.push_back(make_rect({lo.x, lo.y, 0}, {sx, 0, 0}, {0, sy, 0}, {0, 0, 1}, 0));
  if (solids.ceiling_index() >= 0)
    out.push_back(
        make_rect({lo.x, lo.y, hi.z}, {0, sy, 0}, {sx, 0, 0}, {0, 0, -1}, solids.ceiling_index()));
  const double top = std::min(sc.wall_height_m, hi.z);  // above the bounds nothing is kept
  if (solids.wall_index(0) >= 0 && top > 0) {
    struct Face {
      Vec3 origin, u, normal;
    };
    const Face faces[4] = {{{lo.x, hi.y, 0}, {sx, 0, 0}, {0, -1, 0}},
                           {{lo.x, lo.y, 0}, {sx, 0, 0}, {0, 1, 0}},
                           {{hi.x, lo.y, 0}, {0, sy, 0}, {-1, 0, 0}},
                           {{lo.x, lo.y, 0}, {0, sy, 0}, {1, 0, 0}}};
    for (int k = 0; k < 4; ++k)
      out.push_back(make_rect(faces[k].origin, faces[k].u, {0, 0, top}, faces[k].normal,
                              solids.wall_index(k)));
  }
  for (size_t i = 0; i < sc.boxes.size(); ++i) {
    const int id = solids.box_index(i);
    const Solid& s = solids.solids()[static_cast<size_t>(id)];
    const Vec3 axes[3] = {{s.cos_yaw, s.sin_yaw, 0}, {-s.sin_yaw, s.cos_yaw, 0}, {0, 0, 1}};
    const double half[3] = {s.half.x, s.half.y, s.half.z};
    for (int a = 0; a < 3; ++a) {
      const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
      for (const double sign : {-1.0, 1.0}) {
        const Vec3 n = sign * axes[a];
        const Vec3 corner = s.center + half[a] * n - half[b1] * axes[b1] - half[b2] * axes[b2];
        out.push_back(make_rect(corner, 2 * half[b1] * axes[b1], 2 * half[b2] * axes[b2], n, id));
      }
    }
  }
  for (size_t i = 0; i < sc.cylinders.size(); ++i) {
    const CylinderSpec& c = sc.cylinders[i];
    const int id = solids.cylinder_index(i);
    const double hh = 0.5 * c.height_m, r = c.radius_m;
    out.push_back({.kind = Surface::Kind::kCylinderSide,
                   .owner = id,
                   .origin = c.center_m - Vec3{0, 0, hh},
                   .radius = r,
                   .height = c.height_m,
                   .area = kTwoPi * r * c.height_m,
                   .box = solids.solids()[static_cast<size_t>(id)].box});
    out.push_back(make_disk(c.center_m + Vec3{0, 0, hh}, r, 1, id));
    out.push_back(make_disk(c.center_m - Vec3{0, 0, hh}, r, -1, id));
  }
  return out;
}

// Uniform doubles in [0, 1) from the 53 high bits: the same on every standard library.
class Uniform {
 public:
  explicit Uniform(uint64_t seed) : rng_(seed) {}
  double operator()() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

 private:
  std::mt19937_64 rng_;
};

uint64_t draw_count(double area, double density, Uniform& u) {
  return static_cast<uint64_t>(std::floor(area * density + u()));
}

class Sampler {
 public:
  Sampler(const SceneSpec& scene, const SceneSolids& solids, const SamplingOptions& o)
      : solids_(solids.solids()), density_(o.density_per_m2), u_(o.seed) {
    const double e = kHiddenTolerance;
    lo_ = scene.min_m - Vec3{e, e, e};
    hi_ = scene.max_m + Vec3{e, e, e};
  }

  void sample(const Surface& s, SurfaceSamples* out) {
    candidates_.clear();
    for (size_t i = 0; i < solids_.size(); ++i)
      if (static_cast<int>(i) != s.owner && solids_[i].box.overlaps(s.box, kHiddenTolerance))
        candidates_.push_back(&solids_[i]);
    sampled_ = 0;
    const size_t begin = out->points.size();
    out_ = out;
    switch (s.kind) {
      case Surface::Kind::kRect:
        for (uint64_t n = draw_count(s.area, density_, u_); n > 0; --n) {
          const double a = u_(), b = u_();
          offer(s.origin + a * s.u + b * s.v, s.normal);
        }
        break;
      case Surface::Kind::kDisk:
        for (uint64_t n = draw_count(s.area, density_, u_); n > 0; --n) {
          const double r = s.radius * std::sqrt(u_()), th = kTwoPi * u_();
          offer(s.origin + Vec3{r * std::cos(th), r * std::sin(th), 0}, s.normal);
        }
        break;
      case Surface::Kind::kCylinderSide:
        for (uint64_t n = draw_count(s.area, density_, u_); n > 0; --n) {
          const double th = kTwoPi * u_(), z = s.height * u_();
          const Vec3 radial{std::cos(th), std::sin(th), 0};
          offer(s.origin + s.radius * radial + Vec3{0, 0, z}, radial);
        }
        break;
      case Surface::Kind::kMesh:
        for (const auto& t : s.mesh->triangles) {
          const Vec3 &p0 = s.mesh->vertices[t[0]], &p1 = s.mesh->vertices[t[1]],
                     &p2 = s.mesh->vertices[t[2]];
          const Vec3 c = cross(p1 - p0, p2 - p0);
          const double twice_area = norm(c);
          if (!(twice_area > 0)) continue;  // degenerate: no area, no normal
          const Vec3 n = (1.0 / twice_area) * c;
          for (uint64_t k = draw_count(0.5 * twice_area, density_, u_); k > 0; --k) {
            const double r1 = std::sqrt(u_()), b = u_();
            offer((1 - r1) * p0 + (r1 * (1 - b)) * p1 + (r1 * b) * p2, n);
          }
        }
        break;
    }
    records_.push_back({s.area, sampled_, begin, out->points.size()});
  }

  // Drops the points the meshes hide (MeshOcclusion), then sums the visible area: each
  // surface's area times the fraction of its samples kept.
  void finish(const MeshOcclusion* occlusion, SurfaceSamples* out) const {
    std::vector<uint8_t> keep(out->points.size(), 1);
    if (occlusion != nullptr && !occlusion->empty()) {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, keep.size(), 1024), [&](const auto& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          const auto& p = out->points[i];
          const auto& n = out->normals[i];
          keep[i] = occlusion->exposed({p[0], p[1], p[2]}, {n[0], n[1], n[2]}) ? 1 : 0;
        }
      });
    }
    size_t w = 0;
    out->area_m2 = 0;
    for (const Record& r : records_) {
      uint64_t kept = 0;
      for (size_t i = r.begin; i < r.end; ++i) {
        if (keep[i] == 0) continue;
        out->points[w] = out->points[i];
        out->normals[w] = out->normals[i];
        ++w;
        ++kept;
      }
      if (r.sampled > 0)
        out->area_m2 += r.area * static_cast<double>(kept) / static_cast<double>(r.sampled);
    }
    out->points.resize(w);
    out->normals.resize(w);
  }

 private:
  struct Record {  // one surface: its area, its samples, where its kept points lie
    double area;
    uint64_t sampled;
    size_t begin, end;
  };

  void offer(const Vec3& p, const Vec3& n) {
    ++sampled_;
    if (p.x < lo_.x || p.y < lo_.y || p.z < lo_.z || p.x > hi_.x || p.y > hi_.y || p.z > hi_.z)
      return;
    for (const Solid* solid : candidates_)
      if (solid->contains(p, kHiddenTolerance)) return;
    out_->points.push_back(
        {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
    out_->normals.push_back(
        {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)});
  }

  const std::vector<Solid>& solids_;
  double density_;
  Uniform u_;
  Vec3 lo_, hi_;
  std::vector<const Solid*> candidates_;
  uint64_t sampled_ = 0;
  SurfaceSamples* out_ = nullptr;
  std::vector<Record> records_;
};

}  // namespace

Result<SurfaceSamples, std::string> sample_surfaces(const SceneSpec& scene,
                                                    const std::vector<TriangleMesh>& placed_meshes,
                                                    const SamplingOptions& options) {
  const double d = options.density_per_m2;
  if (!(d > 0) || !std::isfinite(d)) {
    std::ostringstream msg;
    msg << "surface sampling: the density must be a positive number of points per m2, not " << d;
    return make_unexpected(msg.str());
  }
  if (options.visibility_rays < 0)
    return make_unexpected(
        "surface sampling: visibility_rays must be 0 (no mesh visibility test) "
        "or a number of ray directions, not " +
        std::to_string(options.visibility_rays));
  const SceneSolids solids(scene, {});
  std::vector<Surface> surfaces = room_and_solid_surfaces(scene, solids);
  for (const TriangleMesh& m : placed_meshes) {
    Surface s{.kind = Surface::Kind::kMesh, .mesh = &m};
    for (const auto& t : m.triangles) s.area += mesh_triangle_area(m, t);
    for (const Vec3& v : m.vertices) s.box.add(v);
    surfaces.push_back(s);
  }

  double total_area = 0;
  for (const Surface& s : surfaces) total_area += s.area;
  const double expected = total_area * d;
  if (expected > static_cast<double>(options.max_points)) {
    char msg[320];
    std::snprintf(msg, sizeof msg,
                  "surface sampling: %.0f points/m2 over %.1f m2 of surfaces would make %.3g "
                  "points, more than the limit of %zu; use a density of at most %.0f points/m2 "
                  "(or raise the limit)",
                  d, total_area, expected, options.max_points,
                  std::floor(static_cast<double>(options.max_points) / total_area));
    return make_unexpected(std::string(msg));
  }

  SurfaceSamples out;
  const auto reserve = static_cast<size_t>(expected) + surfaces.size();
  out.points.reserve(reserve);
  out.normals.reserve(reserve);
  Sampler sampler(scene, solids, options);
  for (const Surface& s : surfaces) sampler.sample(s, &out);
  if (options.visibility_rays > 0 && !placed_meshes.empty()) {
    const MeshOcclusion occlusion(placed_meshes, options.visibility_rays);
    sampler.finish(&occlusion, &out);
  } else {
    sampler.finish(nullptr, &out);
  }
  return out;
}

}  // namespace scancrew::sim
