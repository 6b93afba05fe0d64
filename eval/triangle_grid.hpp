#pragma once

// TriangleGrid: the triangles of a mesh bucketed in a uniform grid, to answer "the nearest
// point of the mesh within r of p" (the reconstruction error, eval/reconstruction_error.hpp).
//
// Each triangle is listed in every cell that its bounding box, grown by r, overlaps (for a
// triangle whose box spans many cells, only the cells that can hold a point within r of it),
// so a query reads the one cell that holds p and tests its triangles: first against their
// bounding boxes, then exactly (closest point on a triangle, Ericson, "Real-Time Collision
// Detection", 2005, 5.1.5). The cell is 2 r wide unless the grid would exceed max_cells, in
// which case cells grow (queries test more triangles; the answer is the same).
//
// Memory: 4 bytes a cell, 4 bytes a (cell, triangle) entry, 100 bytes a triangle. Immutable
// once built; nearest() is thread safe and allocates nothing. Ties (two triangles at the same
// distance) go to the lower triangle index, so the answer does not depend on the build.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/io/triangle_mesh.hpp"
#include "core/result.hpp"

namespace scancrew::eval {

using Point3 = std::array<double, 3>;

// The point of the triangle (a, b, c) closest to p; exact up to rounding, also for a
// degenerate triangle (a segment or a point). vec3::closest_point_on_triangle on arrays.
Point3 closest_point_on_triangle(const Point3& p, const Point3& a, const Point3& b,
                                 const Point3& c);

struct NearestPoint {
  uint32_t triangle = 0;  // index in the mesh
  double distance_m = 0;
  Point3 point{};  // on the mesh
};

class TriangleGrid {
 public:
  static constexpr size_t kDefaultMaxCells = size_t{1} << 24U;  // 64 MB of cell offsets
  // the build's work: the cells of the triangles' boxes, summed (about a second)
  static constexpr uint64_t kDefaultMaxCellVisits = uint64_t{1} << 28U;

  // The mesh's vertices must be finite and its indices in range (reconstruction_error()
  // checks both). An empty mesh gives a grid that finds nothing. Fails when radius_m is not
  // positive and finite, when the triangles' boxes span more than max_cell_visits cells (so the
  // cost is bounded whatever the file holds), or when the grid would hold more than 2^32
  // entries.
  static Result<TriangleGrid, std::string> build(const io::TriangleMesh& mesh, double radius_m,
                                                 size_t max_cells = kDefaultMaxCells,
                                                 uint64_t max_cell_visits = kDefaultMaxCellVisits);

  // The nearest point of the mesh at most radius_m from p, if any.
  std::optional<NearestPoint> nearest(const Point3& p) const;

  double radius_m() const { return radius_m_; }
  double cell_size_m() const { return cell_m_; }
  size_t cells() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  size_t entries() const { return entries_.size(); }

 private:
  TriangleGrid() = default;

  // Calls f(cell index) for every cell listing triangle t, in the same order every time.
  template <class F>
  void for_each_cell(size_t t, F&& f) const;
  // The first and last cells (per axis) of triangle t's box grown by reach().
  std::pair<std::array<int64_t, 3>, std::array<int64_t, 3>> cell_box(size_t t) const;
  // the radius grown a little so that rounding cannot drop a cell at exactly r
  double reach() const { return radius_m_ * (1 + 1e-6) + 1e-9; }
  // build()'s steps (triangle_grid.cpp)
  void load_triangles(const io::TriangleMesh& mesh, Point3& lo, Point3& hi);
  size_t size_grid(const Point3& lo, const Point3& hi, size_t max_cells);
  void renumber();
  std::string fill_cells(size_t cells);

  double radius_m_ = 0;
  double cell_m_ = 0;
  Point3 origin_{};
  std::array<int64_t, 3> dims_{};
  // triangles in the grid's order (see build()); original_ maps them to the mesh's indices
  std::vector<std::array<double, 9>> corners_;  // a, b, c
  std::vector<std::array<float, 6>> bounds_;    // min, max, rounded outwards
  std::vector<uint32_t> original_;
  std::vector<uint32_t> offsets_;  // cell i lists entries_[offsets_[i], offsets_[i+1])
  std::vector<uint32_t> entries_;  // triangles in the grid's order, ascending within a cell
};

}  // namespace scancrew::eval
