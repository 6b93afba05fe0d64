#include "core/motion/replan_request.hpp"

namespace scancrew::motion {

const char* to_string(ReplanReason reason) {
  switch (reason) {
    case ReplanReason::kUtility:
      return "utility";
    case ReplanReason::kObstacle:
      return "obstacle";
    case ReplanReason::kRedundancy:
      return "redundancy";
    case ReplanReason::kTrafficStuck:
      return "traffic_stuck";
    case ReplanReason::kInfeasible:
      return "infeasible";
    case ReplanReason::kTourDone:
      return "tour_done";
  }
  return "?";
}

}  // namespace scancrew::motion
