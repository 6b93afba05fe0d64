#include "core/robot/robot_kind.hpp"

namespace scancrew::robot {

const char* to_string(RobotKind kind) {
  return name_of(kRobotKindNames, kind).data();  // the table's names are literals
}

Result<RobotKind, std::string> parse_robot_kind(std::string_view name) {
  if (const auto kind = value_of(kRobotKindNames, name)) return *kind;
  return make_unexpected("unknown robot kind '" + std::string(name) + "' (ground | multirotor)");
}

}  // namespace scancrew::robot
