#include "eval/triangle_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/vec3_math.hpp"

namespace scancrew::eval {

namespace {

double distance2(const Point3& a, const Point3& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return dx * dx + dy * dy + dz * dz;
}

msg::Vec3 vec(const Point3& p) {
  return {p[0], p[1], p[2]};
}

// float bounds that contain the double ones, so that a box test on them never rejects a
// triangle that is within reach
float round_down(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity())
                                    : f;
}
float round_up(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

Point3 corner(const std::array<double, 9>& c, size_t i) {
  return {c[3 * i], c[3 * i + 1], c[3 * i + 2]};
}

}  // namespace

Point3 closest_point_on_triangle(const Point3& p, const Point3& a, const Point3& b,
                                 const Point3& c) {
  const msg::Vec3 q = vec3::closest_point_on_triangle(vec(p), vec(a), vec(b), vec(c));
  return {q.x, q.y, q.z};
}

std::pair<std::array<int64_t, 3>, std::array<int64_t, 3>> TriangleGrid::cell_box(size_t t) const {
  const double reach = this->reach();
  const auto& c = corners_[t];
  std::array<int64_t, 3> first{}, last{};
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min({c[k], c[3 + k], c[6 + k]}) - reach;
    const double hi = std::max({c[k], c[3 + k], c[6 + k]}) + reach;
    const auto cell = [&](double x) {
      return std::clamp(static_cast<int64_t>(std::floor((x - origin_[k]) / cell_m_)), int64_t{0},
                        dims_[k] - 1);
    };
    first[k] = cell(lo);
    last[k] = cell(hi);
  }
  return {first, last};
}

template <class F>
void TriangleGrid::for_each_cell(size_t t, F&& f) const {
  const double reach = this->reach();
  const auto& c = corners_[t];
  const auto [first, last] = cell_box(t);
  // a triangle whose box spans many cells (a large wall) lists only the cells whose centre is
  // within reach + half a cell diagonal of it: any point within r of it lies in one of them
  const int64_t spanned =
      (last[0] - first[0] + 1) * (last[1] - first[1] + 1) * (last[2] - first[2] + 1);
  const bool filter = spanned > 27;
  const double keep2 = std::pow(reach + cell_m_ * std::sqrt(3.0) / 2, 2);
  const Point3 a = corner(c, 0), b = corner(c, 1), cc = corner(c, 2);
  for (int64_t z = first[2]; z <= last[2]; ++z)
    for (int64_t y = first[1]; y <= last[1]; ++y)
      for (int64_t x = first[0]; x <= last[0]; ++x) {
        if (filter) {
          const Point3 centre{origin_[0] + (static_cast<double>(x) + 0.5) * cell_m_,
                              origin_[1] + (static_cast<double>(y) + 0.5) * cell_m_,
                              origin_[2] + (static_cast<double>(z) + 0.5) * cell_m_};
          if (distance2(centre, closest_point_on_triangle(centre, a, b, cc)) > keep2) continue;
        }
        f(static_cast<size_t>((z * dims_[1] + y) * dims_[0] + x));
      }
}

// fills corners_ and bounds_ from the mesh; lo, hi: the mesh's bounding box
void TriangleGrid::load_triangles(const io::TriangleMesh& mesh, Point3& lo, Point3& hi) {
  const size_t n = mesh.triangles.size();
  corners_.resize(n);
  bounds_.resize(n);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  lo = {kInf, kInf, kInf};
  hi = {-kInf, -kInf, -kInf};
  for (size_t t = 0; t < n; ++t) {
    auto& c = corners_[t];
    for (size_t i = 0; i < 3; ++i) {
      const msg::Vec3& v = mesh.vertices[mesh.triangles[t][i]];
      c[3 * i] = v.x;
      c[3 * i + 1] = v.y;
      c[3 * i + 2] = v.z;
    }
    for (int k = 0; k < 3; ++k) {
      const double t_lo = std::min({c[k], c[3 + k], c[6 + k]});
      const double t_hi = std::max({c[k], c[3 + k], c[6 + k]});
      bounds_[t][k] = round_down(t_lo);
      bounds_[t][3 + k] = round_up(t_hi);
      lo[k] = std::min(lo[k], t_lo);
      hi[k] = std::max(hi[k], t_hi);
    }
  }
}

// sets origin_, cell_m_ and dims_ for the box [lo, hi]; returns the number of cells
size_t TriangleGrid::size_grid(const Point3& lo, const Point3& hi, size_t max_cells) {
  // the grid: cells of 2 r over the mesh's box grown by r, larger if there would be too many
  const double pad = radius_m_ * 1.001;
  double volume = 1;
  for (int k = 0; k < 3; ++k) {
    origin_[k] = lo[k] - pad;
    volume *= hi[k] - lo[k] + 2 * pad;
  }
  cell_m_ = std::max(cell_m_, std::cbrt(volume / static_cast<double>(max_cells)));
  for (;;) {
    size_t cells = 1;
    for (int k = 0; k < 3; ++k) {
      dims_[k] = std::max<int64_t>(
          1, static_cast<int64_t>(std::ceil((hi[k] - lo[k] + 2 * pad) / cell_m_)));
      cells *= static_cast<size_t>(dims_[k]);
    }
    if (cells <= max_cells) break;
    cell_m_ *= 1.05;
  }
  return static_cast<size_t>(dims_[0] * dims_[1] * dims_[2]);
}

// renumbers the triangles (corners_, bounds_, original_) in the order of their first cells
void TriangleGrid::renumber() {
  const size_t n = corners_.size();
  // triangles renumbered in the order of the cells holding their first corners: the triangles
  // one query tests then lie close together in memory (3x faster on a shuffled mesh)
  std::vector<std::pair<size_t, uint32_t>> order(n);
  for (size_t t = 0; t < n; ++t) {
    size_t cell = 0;
    for (int k = 2; k >= 0; --k)
      cell = cell * static_cast<size_t>(dims_[k]) +
             static_cast<size_t>(
                 std::clamp(static_cast<int64_t>((corners_[t][k] - origin_[k]) / cell_m_),
                            int64_t{0}, dims_[k] - 1));
    order[t] = {cell, static_cast<uint32_t>(t)};
  }
  std::sort(order.begin(), order.end());
  original_.resize(n);
  std::vector<std::array<double, 9>> corners(n);
  std::vector<std::array<float, 6>> bounds(n);
  for (size_t t = 0; t < n; ++t) {
    original_[t] = order[t].second;
    corners[t] = corners_[order[t].second];
    bounds[t] = bounds_[order[t].second];
  }
  corners_ = std::move(corners);
  bounds_ = std::move(bounds);
}

// fills offsets_ and entries_, the triangles of each of the cells; the problem if too many
std::string TriangleGrid::fill_cells(size_t cells) {
  const size_t n = corners_.size();
  // counting sort of (cell, triangle): count, prefix sum, fill in triangle order
  std::vector<uint64_t> counts(cells + 1, 0);
  for (size_t t = 0; t < n; ++t) for_each_cell(t, [&](size_t cell) { ++counts[cell + 1]; });
  for (size_t i = 1; i <= cells; ++i) counts[i] += counts[i - 1];
  if (counts[cells] > std::numeric_limits<uint32_t>::max())
    return "the mesh needs " + std::to_string(counts[cells]) +
           " grid entries, more than 2^32 (too many triangles for this radius)";
  offsets_.assign(counts.begin(), counts.end());
  entries_.resize(counts[cells]);
  for (size_t t = 0; t < n; ++t)
    for_each_cell(t, [&](size_t cell) { entries_[counts[cell]++] = static_cast<uint32_t>(t); });
  return {};
}

Result<TriangleGrid, std::string> TriangleGrid::build(const io::TriangleMesh& mesh, double radius_m,
                                                      size_t max_cells, uint64_t max_cell_visits) {
  if (!(radius_m > 0) || !std::isfinite(radius_m))
    return make_unexpected("the search radius must be positive and finite, not " +
                           std::to_string(radius_m));
  max_cells = std::max<size_t>(max_cells, 1);
  TriangleGrid g;
  g.radius_m_ = radius_m;
  g.cell_m_ = 2 * radius_m;
  const size_t n = mesh.triangles.size();
  if (n == 0) return g;
  if (n > std::numeric_limits<uint32_t>::max())
    return make_unexpected("the mesh has " + std::to_string(n) + " triangles, more than 2^32");

  // per-triangle corners and float bounds; the mesh's bounding box
  Point3 lo{}, hi{};
  g.load_triangles(mesh, lo, hi);
  const size_t cells = g.size_grid(lo, hi, max_cells);

  // the build visits every cell of each triangle's box: bounded before it starts (20,000
  // triangles that each spanned the scene, a 260 KB file, took 150 s); a reconstruction's
  // triangles are a voxel or two, a few cells each
  uint64_t visits = 0;
  for (size_t t = 0; t < n && visits <= max_cell_visits; ++t) {
    const auto [first, last] = g.cell_box(t);
    visits += static_cast<uint64_t>((last[0] - first[0] + 1) * (last[1] - first[1] + 1) *
                                    (last[2] - first[2] + 1));
  }
  if (visits > max_cell_visits)
    return make_unexpected("the mesh's " + std::to_string(n) + " triangles span more than " +
                           std::to_string(max_cell_visits) + " cells of " +
                           std::to_string(g.cell_m_) +
                           " m: triangles far larger than the search radius " +
                           std::to_string(radius_m) + " m (not a reconstruction at this scale)");

  g.renumber();
  if (std::string problem = g.fill_cells(cells); !problem.empty()) return make_unexpected(problem);
  return g;
}

std::optional<NearestPoint> TriangleGrid::nearest(const Point3& p) const {
  if (offsets_.empty()) return std::nullopt;
  int64_t cell = 0;
  for (int k = 2; k >= 0; --k) {
    const double x = (p[k] - origin_[k]) / cell_m_;
    if (!(x >= 0) || x >= static_cast<double>(dims_[k])) return std::nullopt;  // NaN too
    cell = cell * dims_[k] + static_cast<int64_t>(x);
  }
  std::optional<NearestPoint> best;
  double best2 = radius_m_ * radius_m_;
  const auto c = static_cast<size_t>(cell);
  for (size_t e = offsets_[c]; e < offsets_[c + 1]; ++e) {
    const uint32_t t = entries_[e];
    const auto& box = bounds_[t];
    double box2 = 0;
    for (int k = 0; k < 3; ++k) {
      // branch-free: which side p lies on is unpredictable, and this loop is the query's cost
      const double out = std::max(
          {static_cast<double>(box[k]) - p[k], p[k] - static_cast<double>(box[3 + k]), 0.0});
      box2 += out * out;
    }
    if (box2 > best2) continue;
    const auto& tc = corners_[t];
    const Point3 q = closest_point_on_triangle(p, corner(tc, 0), corner(tc, 1), corner(tc, 2));
    const double d2 = distance2(p, q);
    if (d2 < best2 || (d2 == best2 && (!best || original_[t] < best->triangle))) {
      best2 = d2;
      best = NearestPoint{.triangle = original_[t], .distance_m = std::sqrt(d2), .point = q};
    }
  }
  return best;
}

}  // namespace scancrew::eval
