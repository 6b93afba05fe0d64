#include "eval/missed_points.hpp"

#include <cmath>

#include "eval/reconstruction_error.hpp"
#include "eval/triangle_grid.hpp"

namespace scancrew::eval {

namespace {
// up / down: the normal within 45° of ±z
constexpr double kVerticalCos = 0.70710678118654752440;  // cos 45°
// the bands' outer edges in e_max
constexpr double kNearEdge = 2.0;
constexpr double kOffEdge = 4.0;
}  // namespace

size_t MissProfile::band_total(MissBand b) const {
  size_t n = 0;
  for (const auto& row : counts) n += row[static_cast<size_t>(b)];
  return n;
}

size_t MissProfile::facing_total(Facing f) const {
  size_t n = 0;
  for (const size_t c : counts[static_cast<size_t>(f)]) n += c;
  return n;
}

Facing facing_of(const std::array<float, 3>& normal) {
  const double length = std::sqrt(static_cast<double>(normal[0]) * normal[0] +
                                  static_cast<double>(normal[1]) * normal[1] +
                                  static_cast<double>(normal[2]) * normal[2]);
  const double nz = normal[2] / length;
  if (nz >= kVerticalCos) return Facing::kUp;
  if (nz <= -kVerticalCos) return Facing::kDown;
  return Facing::kSide;
}

const char* to_string(MissBand b) {
  switch (b) {
    case MissBand::kNear:
      return "near";
    case MissBand::kOff:
      return "off";
    case MissBand::kHole:
      return "hole";
  }
  return "?";
}

const char* to_string(Facing f) {
  switch (f) {
    case Facing::kUp:
      return "up";
    case Facing::kSide:
      return "side";
    case Facing::kDown:
      return "down";
  }
  return "?";
}

Result<MissProfile, std::string> profile_misses(const io::TriangleMesh& mesh,
                                                std::span<const std::array<float, 3>> points,
                                                std::span<const std::array<float, 3>> normals,
                                                double e_max_m) {
  if (auto ok = check_eval_inputs(mesh, points, normals, e_max_m); !ok)
    return make_unexpected(ok.error());
  MissProfile out;
  out.e_max_m = e_max_m;
  out.points = points.size();
  auto grid = TriangleGrid::build(mesh, kOffEdge * e_max_m);
  if (!grid) return make_unexpected(grid.error());
  for (size_t i = 0; i < points.size(); ++i) {
    const auto hit = grid->nearest({points[i][0], points[i][1], points[i][2]});
    const MissBand band = !hit                                     ? MissBand::kHole
                          : hit->distance_m <= kNearEdge * e_max_m ? MissBand::kNear
                                                                   : MissBand::kOff;
    ++out.counts[static_cast<size_t>(facing_of(normals[i]))][static_cast<size_t>(band)];
  }
  return out;
}

}  // namespace scancrew::eval
