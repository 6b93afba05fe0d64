#include "core/robot/robot_kind.hpp"

namespace scancrew::robot {

const char* to_string(RobotKind kind) {
  return kind == RobotKind::kGround ? "ground" : "multirotor";
}

Result<RobotKind, std::string> parse_robot_kind(std::string_view name) {
  if (name == "ground") return RobotKind::kGround;
  if (name == "multirotor") return RobotKind::kMultirotor;
  return make_unexpected("unknown robot kind '" + std::string(name) + "' (ground | multirotor)");
}

}  // namespace scancrew::robot
