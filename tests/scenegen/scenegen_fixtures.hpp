#pragma once

// Helpers shared by the scenegen tests: a candidate or a generated scene, names, the
// solids' z ranges.

#include <string>

#include "scenegen/draw.hpp"

namespace scancrew::scenegen::testing {

inline bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

inline double bottom(const sim::BoxSpec& b) {
  return b.center_m.z - 0.5 * b.size_m.z;
}
inline double top(const sim::BoxSpec& b) {
  return b.center_m.z + 0.5 * b.size_m.z;
}
inline double bottom(const sim::CylinderSpec& c) {
  return c.center_m.z - 0.5 * c.height_m;
}
inline double top(const sim::CylinderSpec& c) {
  return c.center_m.z + 0.5 * c.height_m;
}

// one candidate, as drawn (before the free-space check and any redraw)
inline Candidate candidate(Family family, uint64_t seed) {
  Rng rng(seed);
  return family == Family::kIndoor ? draw_indoor(rng) : draw_outdoor(rng);
}

// the scene generate() returns (checked; aborts the test when it fails)
inline GeneratedScene generated(Family family, uint64_t seed) {
  auto g = generate(family, seed);
  SCANCREW_CHECK(g.has_value(), "generate() failed");
  return std::move(g).value();
}

}  // namespace scancrew::scenegen::testing
