#include "scenegen/footprint.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scancrew::scenegen {

double gap(const Rect& a, const Rect& b) {
  const double dx = std::max({0.0, b.x0 - a.x1, a.x0 - b.x1});
  const double dy = std::max({0.0, b.y0 - a.y1, a.y0 - b.y1});
  return std::sqrt(dx * dx + dy * dy);
}

bool overlaps(const Rect& a, const Rect& b) {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

Rect footprint(const sim::BoxSpec& box) {
  const double c = std::abs(std::cos(box.yaw_rad)), s = std::abs(std::sin(box.yaw_rad));
  const double hx = 0.5 * (c * box.size_m.x + s * box.size_m.y);
  const double hy = 0.5 * (s * box.size_m.x + c * box.size_m.y);
  return {box.center_m.x - hx, box.center_m.y - hy, box.center_m.x + hx, box.center_m.y + hy};
}

Rect footprint(const sim::CylinderSpec& cylinder) {
  const double r = cylinder.radius_m;
  return {cylinder.center_m.x - r, cylinder.center_m.y - r, cylinder.center_m.x + r,
          cylinder.center_m.y + r};
}

sim::BoxSpec make_box(std::string name, const Rect& r, double z0_m, double z1_m, sim::Rgb color) {
  sim::BoxSpec b;
  b.name = std::move(name);
  b.center_m = {0.5 * (r.x0 + r.x1), 0.5 * (r.y0 + r.y1), 0.5 * (z0_m + z1_m)};
  b.size_m = {r.width(), r.depth(), z1_m - z0_m};
  b.color = color;
  return b;
}

bool Layout::fits(const Rect& r, const Rect& inside, double clearance_m) const {
  const Rect room = inside.grown(-clearance_m);
  if (r.x0 < room.x0 || r.y0 < room.y0 || r.x1 > room.x1 || r.y1 > room.y1) return false;
  for (const Rect& s : solids_)
    if (gap(r, s) < clearance_m) return false;
  for (const Rect& k : keep_out_)
    if (overlaps(r, k)) return false;
  return true;
}

double Layout::clearance_at(double x_m, double y_m) const {
  double best = std::numeric_limits<double>::max();
  const Rect p{x_m, y_m, x_m, y_m};
  for (const Rect& s : solids_) best = std::min(best, gap(p, s));
  return best;
}

}  // namespace scancrew::scenegen
