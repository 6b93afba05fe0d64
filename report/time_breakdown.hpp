#pragma once

// Where a robot's mission time goes (the run's metrics.json "time_s", the report's stacked
// bars, sweep tables): each interval of mission time goes to one activity, decided from the
// robot's latest state (msg::RobotState, from its low-level planner) and its ground-truth
// motion, in this order:
//   lost         the robot's link is lost (mode kLost);
//   backing off  it follows a back-off path (RobotState::backing_off);
//   traffic      the traffic policy holds it for a teammate (held_by_robot), or it steps aside;
//   driving      it moves: speed >= kMovingMps;
//   turning      it turns on the spot: speed below that, yaw rate >= kTurningRadps;
//   waiting      it stands with a goal to go to, or asks for one: no state yet, or mode
//                planning / waiting / moving / stopped (a path being computed, a plan being
//                made, an emergency stop being replanned);
//   idle (open)  it stands idle or done while its ISE source still has ISEs to do;
//   idle (done)  it stands idle or done after its ISE source reported completion.
// The shares sum to the mission time (add() is called for every interval).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "interfaces/nav_msgs.hpp"

namespace scancrew::report {

enum class Activity : uint8_t {
  kDriving,
  kTurning,
  kTraffic,
  kWaiting,
  kBackingOff,
  kIdleOpen,
  kIdleDone,
  kLost
};
inline constexpr size_t kActivityCount = 8;
inline constexpr double kMovingMps = 0.05;
inline constexpr double kTurningRadps = 0.1;

// "driving", "turning", "traffic", "waiting", "backing_off", "idle_open", "idle_done", "lost"
// (metrics.json keys)
std::string_view to_string(Activity activity);
// "driving", "turning on the spot", "held by traffic", "waiting for a plan or a path", ...
std::string_view label(Activity activity);

struct ActivityInputs {
  bool have_state = false;
  msg::RobotState::Mode mode = msg::RobotState::Mode::kIdle;
  bool backing_off = false;
  uint32_t held_by_robot = 0;
  double speed_mps = 0;
  double yaw_rate_radps = 0;
  bool source_complete = false;  // the robot's ISE source reports C_ins empty
};

Activity classify(const ActivityInputs& in);

struct TimeBreakdown {
  std::array<double, kActivityCount> seconds{};
  void add(Activity activity, double dt_s) { seconds[static_cast<size_t>(activity)] += dt_s; }
  double of(Activity activity) const { return seconds[static_cast<size_t>(activity)]; }
  double total() const;
};

}  // namespace scancrew::report
