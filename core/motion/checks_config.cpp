#include "core/motion/checks_config.hpp"

namespace scancrew::motion {

ChecksConfig ChecksConfig::for_kind(RobotKind kind) {
  ChecksConfig c;
  c.obstacle = ObstacleCheckConfig::for_kind(kind);
  c.traffic = TrafficConfig::for_kind(kind);
  c.redundancy.planar = kind == RobotKind::kGround;
  return c;
}

std::string ChecksConfig::validate() const {
  std::string e;
  for (const std::string& part : {obstacle.validate(), traffic.validate(), redundancy.validate()})
    if (!part.empty()) e += (e.empty() ? "" : "; ") + part;
  return e;
}

}  // namespace scancrew::motion
