// The families' names and robot kinds, and the passages' names.

#include "scenegen/scenegen.hpp"

namespace scancrew::scenegen {

std::string to_string(Family family) {
  return family == Family::kIndoor ? "indoor" : "outdoor";
}

std::optional<Family> parse_family(std::string_view name) {
  if (name == "indoor") return Family::kIndoor;
  if (name == "outdoor") return Family::kOutdoor;
  return std::nullopt;
}

robot::RobotKind robot_kind(Family family) {
  return family == Family::kIndoor ? robot::RobotKind::kGround : robot::RobotKind::kMultirotor;
}

std::string to_string(Passage::Kind kind) {
  switch (kind) {
    case Passage::Kind::kDoorway:
      return "doorway";
    case Passage::Kind::kCorridor:
      return "corridor";
    case Passage::Kind::kColonnadeGap:
      return "colonnade gap";
    case Passage::Kind::kGallery:
      return "gallery";
  }
  return "?";
}

}  // namespace scancrew::scenegen
