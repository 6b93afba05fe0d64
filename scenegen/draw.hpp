#pragma once

// The generators' inner interface (scenegen/generate.cpp calls these): one candidate scene
// per call from the stream it is given, before the free-space check. Not part of the
// library's public interface.

#include <string>
#include <vector>

#include "scenegen/footprint.hpp"
#include "scenegen/random.hpp"
#include "scenegen/scenegen.hpp"

namespace scancrew::scenegen {

struct Candidate {
  sim::SceneSpec scene;  // without starts
  std::vector<Passage> passages;
  // free-standing objects that a repair may drop, last drawn last: each the names of its
  // boxes and cylinders
  std::vector<std::vector<std::string>> removable;
  Layout layout;       // every solid's footprint, for choosing starts
  std::string defect;  // why the candidate cannot be used (then it is drawn again); empty: fine
};

Candidate draw_indoor(Rng& rng);
Candidate draw_outdoor(Rng& rng);

// Up to `count` start poses spread over the scene: points on a grid over the bounds whose
// footprint clearance is at least clearance_m, chosen farthest-first from a drawn one; z is
// z_m; each faces the middle of the bounds (whole degrees). `skip` lists points not to use
// (starts a check found not free).
std::vector<sim::StartPose> choose_starts(const Candidate& c, Rng& rng, size_t count,
                                          double clearance_m, double z_m,
                                          const std::vector<sim::StartPose>& skip = {});

}  // namespace scancrew::scenegen
