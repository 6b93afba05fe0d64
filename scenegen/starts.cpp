// Start poses spread over a candidate scene: farthest-first over the free grid points.

#include <algorithm>
#include <cmath>
#include <limits>

#include "scenegen/draw.hpp"

namespace scancrew::scenegen {

std::vector<sim::StartPose> choose_starts(const Candidate& c, Rng& rng, size_t count,
                                          double clearance_m, double z_m,
                                          const std::vector<sim::StartPose>& skip) {
  constexpr double kStep = 0.5;  // grid pitch, m
  const sim::SceneSpec& s = c.scene;
  // grid points at least clearance_m from every footprint and from the bounds' edges
  std::vector<std::pair<double, double>> free;
  const int nx = static_cast<int>((s.max_m.x - s.min_m.x - 2 * clearance_m) / kStep);
  const int ny = static_cast<int>((s.max_m.y - s.min_m.y - 2 * clearance_m) / kStep);
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j) {
      const double x = cm(s.min_m.x + clearance_m + i * kStep);
      const double y = cm(s.min_m.y + clearance_m + j * kStep);
      if (c.layout.clearance_at(x, y) < clearance_m) continue;
      const bool skipped = std::any_of(skip.begin(), skip.end(), [&](const sim::StartPose& p) {
        return std::hypot(p.position_m.x - x, p.position_m.y - y) < kStep;
      });
      if (!skipped) free.emplace_back(x, y);
    }
  std::vector<sim::StartPose> starts;
  if (free.empty()) return starts;

  // farthest first from a drawn point; each faces the middle of the bounds
  std::vector<double> nearest(free.size(), std::numeric_limits<double>::max());
  size_t next = static_cast<size_t>(rng.integer(0, static_cast<int>(free.size()) - 1));
  const double mid_x = 0.5 * (s.min_m.x + s.max_m.x), mid_y = 0.5 * (s.min_m.y + s.max_m.y);
  while (starts.size() < count) {
    const auto [x, y] = free[next];
    const double yaw_deg = std::round(std::atan2(mid_y - y, mid_x - x) * 180.0 / M_PI);
    starts.push_back({{x, y, z_m}, yaw_deg * M_PI / 180.0});
    size_t best = 0;
    for (size_t k = 0; k < free.size(); ++k)
      nearest[k] = std::min(nearest[k], std::hypot(free[k].first - x, free[k].second - y));
    for (size_t k = 1; k < free.size(); ++k)
      if (nearest[k] > nearest[best]) best = k;
    if (nearest[best] <= 0) break;  // fewer free points than starts wanted
    next = best;
  }
  return starts;
}

}  // namespace scancrew::scenegen
