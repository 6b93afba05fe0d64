#pragma once

// SceneSolids: the solid obstacles of a scene, placed exactly as build_mjcf() places them —
// boxes turned by their yaw, upright cylinders, the four wall slabs, the ceiling slab and the
// half-space under the floor (z < 0) — plus the scene's placed meshes (triangle soups: visual
// only in MuJoCo, but real obstacles to sight and to planning). sample_surfaces() hides the
// points buried in a solid with it; the reachable ground truth (eval/free_space.hpp,
// eval/reachable_truth.hpp) asks it whether a line of sight is blocked and whether a robot's
// body fits.
//
// Acceleration: the boxes and cylinders are bucketed in a uniform x-y grid (their footprints
// are upright prisms; outdoor scenes have hundreds); the walls, the ceiling and the floor are
// tested always; the meshes' triangles by MeshOcclusion's bounding-volume hierarchy.
//
// Units: metres; z up, the floor is z = 0. Immutable once built; const member functions are
// thread safe and allocate nothing.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "interfaces/geometry.hpp"
#include "sim/mesh_io.hpp"
#include "sim/mesh_occlusion.hpp"
#include "sim/scene.hpp"

namespace scancrew::sim {

// An axis-aligned box; empty (lo > hi) until a point is added.
struct Aabb {
  static constexpr double kBig = 1e30;  // "unbounded"
  msg::Vec3 lo{kBig, kBig, kBig}, hi{-kBig, -kBig, -kBig};
  void add(const msg::Vec3& p);
  bool overlaps(const Aabb& o, double tol) const;
};

// A solid: a box turned by yaw about z, an upright cylinder, or the half-space under the floor.
struct Solid {
  enum class Kind { kBox, kCylinder, kBelowFloor } kind = Kind::kBox;
  msg::Vec3 center, half;  // box: half extents in its own frame; cylinder: half.x radius,
                           // half.z half height
  double cos_yaw = 1, sin_yaw = 0;
  Aabb box;  // world-frame bounds

  // Whether p lies inside the solid grown by eps (strictly).
  bool contains(const msg::Vec3& p, double eps) const;
  // Whether the segment a + t (b - a), t in (t0, t1), enters the solid's interior.
  bool crossed_by(const msg::Vec3& a, const msg::Vec3& b, double t0, double t1) const;
  // Whether the solid's interior overlaps the upright cylinder (x, y, radius, z in [z0, z1]).
  bool overlaps_cylinder(double x, double y, double radius_m, double z0_m, double z1_m) const;
  // Whether the solid's interior overlaps the ball (centre, radius).
  bool overlaps_sphere(const msg::Vec3& center, double radius_m) const;
};

Solid make_box_solid(const msg::Vec3& center, const msg::Vec3& half, double yaw_rad);
Solid make_cylinder_solid(const msg::Vec3& center, double radius_m, double height_m);

class SceneSolids {
 public:
  // The solids of `scene` and the triangles of `placed_meshes` (as load_scene_meshes()
  // returns them; may be empty). Solid order: the floor (index 0), the ceiling (when the scene
  // has one), the four walls (when wall_height_m > 0: +y, -y, +x, -x), the boxes, the
  // cylinders, each in scene order.
  SceneSolids(const SceneSpec& scene, const std::vector<TriangleMesh>& placed_meshes);
  SceneSolids(SceneSolids&&) noexcept;
  SceneSolids& operator=(SceneSolids&&) noexcept;
  ~SceneSolids();

  const std::vector<Solid>& solids() const { return solids_; }
  int ceiling_index() const { return ceiling_; }                          // -1: none
  int wall_index(int k) const { return walls_[static_cast<size_t>(k)]; }  // -1: no walls
  int box_index(size_t i) const { return first_box_ + static_cast<int>(i); }
  int cylinder_index(size_t i) const { return first_cylinder_ + static_cast<int>(i); }
  size_t triangle_count() const;

  // Whether the segment a-b crosses a solid, a mesh triangle or the floor, ignoring
  // end_margin_m at each end (a ground-truth point lies on a surface; a camera may sit on one).
  bool segment_blocked(const msg::Vec3& a, const msg::Vec3& b, double end_margin_m) const;
  // Body clearance against the solids (the floor included) and the mesh triangles: an
  // upright cylinder (a ground robot's footprint, z in [z0_m, z1_m]) and a ball (a multirotor).
  bool cylinder_overlaps(double x, double y, double radius_m, double z0_m, double z1_m) const;
  bool sphere_overlaps(const msg::Vec3& center, double radius_m) const;

 private:
  template <class F>
  bool any_grid_solid(double x0, double y0, double x1, double y1, F&& f) const;

  std::vector<Solid> solids_;
  int ceiling_ = -1;
  std::array<int, 4> walls_{-1, -1, -1, -1};
  int first_box_ = 0, first_cylinder_ = 0;
  std::vector<uint32_t> always_;  // solids tested by every query (floor, ceiling, walls, huge)
  // the x-y grid: cell (i, j) lists grid_entries_[grid_offsets_[c], grid_offsets_[c + 1])
  double grid_x0_ = 0, grid_y0_ = 0, grid_cell_m_ = 1;
  int grid_nx_ = 0, grid_ny_ = 0;
  std::vector<uint32_t> grid_offsets_, grid_entries_;
  std::unique_ptr<MeshOcclusion> meshes_;  // null: no triangles
};

}  // namespace scancrew::sim
