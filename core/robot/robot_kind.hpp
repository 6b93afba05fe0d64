#pragma once

// RobotKind: the two kinds of robot the thesis plans for (2.1): ground robots (SE(2), on the
// floor) and multirotors (x, y, z, yaw). The one type the simulator, ISE feasibility, the
// planners and the evaluation use; a set of kinds is a bit mask (kind_bit).

#include <cstdint>
#include <string>
#include <string_view>

#include "core/enum_names.hpp"
#include "core/result.hpp"

namespace scancrew::robot {

enum class RobotKind : uint8_t { kGround = 0, kMultirotor = 1 };

inline constexpr EnumNames<RobotKind, 2> kRobotKindNames = {
    {{RobotKind::kGround, "ground"}, {RobotKind::kMultirotor, "multirotor"}}};

const char* to_string(RobotKind kind);  // "ground", "multirotor"

// The kind a launch file or scene names; the error names the allowed values.
Result<RobotKind, std::string> parse_robot_kind(std::string_view name);

// A kind as a bit of a set of kinds (msg::Viewpoint::robot_types and the like).
constexpr uint32_t kind_bit(RobotKind kind) {
  return 1U << static_cast<uint32_t>(kind);
}

}  // namespace scancrew::robot
