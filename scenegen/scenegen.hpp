#pragma once

// Procedural scenes for the benchmark (`scancrew scenegen`, docs/scenegen.md): indoor floors
// for ground robots and outdoor sites for multirotors, drawn from one seed. The scene is a
// plain sim::SceneSpec (boxes, cylinders, walls, ceiling) with start poses for the
// family's robot kind; write_scene_yaml() turns it into a scene file that sim::parse_scene
// reads back unchanged. The geometry is the project's own: no assets.
//
// Deterministic: the same family and seed give the same scene, byte for byte once written,
// whatever the standard library (scenegen/random.hpp). generate() is a pure function,
// thread safe, and allocates.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.hpp"
#include "scenegen/footprint.hpp"
#include "sim/robot_model.hpp"
#include "sim/scene.hpp"

namespace scancrew::scenegen {

enum class Family { kIndoor, kOutdoor };
std::string to_string(Family family);
std::optional<Family> parse_family(std::string_view name);  // "indoor" | "outdoor"
robot::RobotKind robot_kind(Family family);                 // ground indoors, multirotor outdoors

// A way through that the generator promises: nothing solid stands in `area` from the floor
// up to clear_height_m, and the way is at least width_m wide (tested).
struct Passage {
  enum class Kind { kDoorway, kCorridor, kColonnadeGap, kGallery };
  Kind kind = Kind::kDoorway;
  std::string name;  // the doorway's wall, the corridor, the gallery
  Rect area;         // on the floor, axis aligned
  double width_m = 0;
  double clear_height_m = 0;
};
std::string to_string(Passage::Kind kind);

// What the free-space check (eval/free_space.hpp) found on the scene returned.
struct FreeSpaceCheck {
  bool connected = false;
  bool starts_free = false;
  size_t free_cells = 0, reachable_cells = 0;
};

struct GeneratedScene {
  sim::SceneSpec scene;  // named <family>_<seed>; scene.starts holds the family's kind's starts
  Family family = Family::kIndoor;
  uint64_t seed = 0;
  std::vector<Passage> passages;
  FreeSpaceCheck free_space;
  int draws = 1;    // candidates drawn (1 + redraws after a failed check)
  int repairs = 0;  // objects dropped or starts replaced to pass the check
};

// Draws a scene of the family from the seed and checks its free space for the family's
// robot kind (connected, every start free), repairing or redrawing a bounded number of
// times from the seed's own stream. The error says what still failed after the last try.
Result<GeneratedScene, std::string> generate(Family family, uint64_t seed);

// The scene as a scene file (docs/sim.md's format, starts included), millimetre
// resolution; a header comment names the generator, family and seed when given.
std::string write_scene_yaml(const sim::SceneSpec& scene, const std::string& header_comment = {});

}  // namespace scancrew::scenegen
