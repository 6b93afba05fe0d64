#include "report/time_breakdown.hpp"

#include <cmath>

namespace scancrew::report {

using Mode = msg::RobotState::Mode;

std::string_view to_string(Activity activity) {
  switch (activity) {
    case Activity::kDriving:
      return "driving";
    case Activity::kTurning:
      return "turning";
    case Activity::kTraffic:
      return "traffic";
    case Activity::kWaiting:
      return "waiting";
    case Activity::kBackingOff:
      return "backing_off";
    case Activity::kIdleOpen:
      return "idle_open";
    case Activity::kIdleDone:
      return "idle_done";
    case Activity::kLost:
      return "lost";
  }
  return "?";
}

std::string_view label(Activity activity) {
  switch (activity) {
    case Activity::kDriving:
      return "driving";
    case Activity::kTurning:
      return "turning on the spot";
    case Activity::kTraffic:
      return "held by traffic";
    case Activity::kWaiting:
      return "waiting for a plan or a path";
    case Activity::kBackingOff:
      return "backing off";
    case Activity::kIdleOpen:
      return "idle, ISEs open";
    case Activity::kIdleDone:
      return "idle after completion";
    case Activity::kLost:
      return "lost";
  }
  return "?";
}

Activity classify(const ActivityInputs& in) {
  if (in.have_state && in.mode == Mode::kLost) return Activity::kLost;
  if (in.have_state && in.backing_off) return Activity::kBackingOff;
  if (in.have_state && (in.held_by_robot != 0 || in.mode == Mode::kSteppingAside))
    return Activity::kTraffic;
  if (in.speed_mps >= kMovingMps) return Activity::kDriving;
  if (std::abs(in.yaw_rate_radps) >= kTurningRadps) return Activity::kTurning;
  if (in.have_state && (in.mode == Mode::kIdle || in.mode == Mode::kDone))
    return in.source_complete ? Activity::kIdleDone : Activity::kIdleOpen;
  return Activity::kWaiting;
}

double TimeBreakdown::total() const {
  double sum = 0;
  for (double s : seconds) sum += s;
  return sum;
}

}  // namespace scancrew::report
