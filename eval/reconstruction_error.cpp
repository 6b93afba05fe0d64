#include "eval/reconstruction_error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "eval/triangle_grid.hpp"

namespace scancrew::eval {

namespace {

// Points per block: blocks are reduced in order, so the sums do not depend on how TBB
// splits the work.
constexpr size_t kBlock = 4096;

// Count, mean and sum of squared deviations, merged as in Chan, Golub and LeVeque (1979):
// stable where summing squares would cancel (a large mean with a tiny spread).
struct Moments {
  size_t n = 0;
  double mean = 0;
  double m2 = 0;

  void add(double x) {
    ++n;
    const double d = x - mean;
    mean += d / static_cast<double>(n);
    m2 += d * (x - mean);
  }
  void merge(const Moments& o) {
    if (o.n == 0) return;
    const double total = static_cast<double>(n + o.n);
    const double d = o.mean - mean;
    mean += d * static_cast<double>(o.n) / total;
    m2 += o.m2 + d * d * static_cast<double>(n) * static_cast<double>(o.n) / total;
    n += o.n;
  }
};

bool finite(const std::array<float, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

std::string format_vec(double x, double y, double z) {
  char text[96];
  std::snprintf(text, sizeof text, "(%g, %g, %g)", x, y, z);
  return text;
}

}  // namespace

Result<void, std::string> check_eval_inputs(const io::TriangleMesh& mesh,
                                            std::span<const std::array<float, 3>> points,
                                            std::span<const std::array<float, 3>> normals,
                                            double e_max_m) {
  if (!(e_max_m > 0) || !std::isfinite(e_max_m))
    return make_unexpected("e_max must be positive and finite, not " + std::to_string(e_max_m) +
                           " m");
  if (normals.size() != points.size())
    return make_unexpected(std::to_string(points.size()) + " ground-truth points but " +
                           std::to_string(normals.size()) + " normals");
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const msg::Vec3& v = mesh.vertices[i];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      return make_unexpected("mesh vertex " + std::to_string(i) + " is not finite " +
                             format_vec(v.x, v.y, v.z));
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const uint32_t v : mesh.triangles[t])
      if (v >= mesh.vertices.size())
        return make_unexpected("mesh triangle " + std::to_string(t) + " refers to vertex " +
                               std::to_string(v) + " of " + std::to_string(mesh.vertices.size()));
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const auto& n = normals[i];
    if (!finite(p))
      return make_unexpected("ground-truth point " + std::to_string(i) + " is not finite " +
                             format_vec(p[0], p[1], p[2]));
    if (!finite(n) || (n[0] == 0 && n[1] == 0 && n[2] == 0))
      return make_unexpected("ground-truth normal " + std::to_string(i) +
                             " is zero or not finite " + format_vec(n[0], n[1], n[2]));
  }
  return {};
}

double max_error_for_voxel(double voxel_size_m) {
  return voxel_size_m * std::sqrt(3.0) / 2;
}

std::string_view to_string(EvalStatus status) {
  switch (status) {
    case EvalStatus::kOk:
      return "ok";
    case EvalStatus::kEmptyMesh:
      return "empty mesh";
    case EvalStatus::kNothingCovered:
      return "nothing covered";
  }
  return "?";
}

Result<ReconstructionError, std::string> reconstruction_error(
    const io::TriangleMesh& mesh, std::span<const std::array<float, 3>> points,
    std::span<const std::array<float, 3>> normals, const ReconstructionErrorConfig& config) {
  if (points.empty()) return make_unexpected(std::string("no ground-truth points"));
  if (auto ok = check_eval_inputs(mesh, points, normals, config.e_max_m); !ok)
    return make_unexpected(ok.error());
  auto grid = TriangleGrid::build(mesh, config.e_max_m);
  if (!grid) return make_unexpected(grid.error());

  ReconstructionError out;
  out.gt_points = points.size();
  out.e_max_m = config.e_max_m;
  out.mesh_triangles = mesh.triangles.size();
  if (config.per_point_error)
    out.point_error_m.assign(points.size(), std::numeric_limits<float>::quiet_NaN());

  // each block of points is scored in order by one thread; blocks are merged in order below
  const size_t blocks = (points.size() + kBlock - 1) / kBlock;
  std::vector<Moments> block_moments(blocks);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks), [&](const auto& range) {
    for (size_t b = range.begin(); b != range.end(); ++b) {
      Moments m;
      const size_t end = std::min(points.size(), (b + 1) * kBlock);
      for (size_t i = b * kBlock; i < end; ++i) {
        const Point3 p{points[i][0], points[i][1], points[i][2]};
        const auto hit = grid->nearest(p);
        if (!hit) continue;
        const Point3 n{normals[i][0], normals[i][1], normals[i][2]};
        const double along = (hit->point[0] - p[0]) * n[0] + (hit->point[1] - p[1]) * n[1] +
                             (hit->point[2] - p[2]) * n[2];
        const double error = along / std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        m.add(error);
        if (config.per_point_error) out.point_error_m[i] = static_cast<float>(error);
      }
      block_moments[b] = m;
    }
  });
  Moments all;
  for (const Moments& m : block_moments) all.merge(m);

  out.covered = all.n;
  out.coverage = static_cast<double>(all.n) / static_cast<double>(points.size());
  if (all.n == 0) {
    out.status = mesh.triangles.empty() ? EvalStatus::kEmptyMesh : EvalStatus::kNothingCovered;
    out.mean_error_m = out.std_error_m = out.rmse_m = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  const double variance = all.m2 / static_cast<double>(all.n);
  out.mean_error_m = all.mean;
  out.std_error_m = std::sqrt(variance);
  out.rmse_m = std::sqrt(all.mean * all.mean + variance);
  return out;
}

}  // namespace scancrew::eval
