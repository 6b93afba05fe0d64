#pragma once

// Why the low-level planner asks for a new plan: the "wait for high-level re-planning" of
// Algorithms 1, 3 and 6 (thesis 2.5.3, 3.5.2, 4.5.2) made a value the low_level component
// can publish. Plain data.

#include <cstdint>
#include <string>

namespace scancrew::motion {

enum class ReplanReason : uint8_t {
  kUtility,       // UtilityCheck: c_thres of the tour's ISEs are done (Alg. 1 line 5)
  kObstacle,      // ObstacleCheck: emergency stop (Alg. 1 line 15)
  kRedundancy,    // RedundancyCheck: the next cluster belongs to a teammate (Alg. 6 line 5)
  kTrafficStuck,  // TrafficPolicy: held longer than max_wait_s (not in the thesis, see docs)
  kInfeasible,    // LazyPRM* found no path to the next goal (Alg. 1 line 10, else branch)
  kTourDone,      // every cluster of the tour was reached
};
const char* to_string(ReplanReason reason);

struct ReplanRequest {
  uint32_t robot_id = 0;
  ReplanReason reason = ReplanReason::kUtility;
  uint32_t because_of_robot = 0;  // the teammate involved (kRedundancy, kTrafficStuck), else 0
  double stamp_s = 0;             // when the check fired (the caller's clock)
  std::string detail;             // one human-readable line for the log
};

}  // namespace scancrew::motion
