#pragma once

// WaypointDriver: drives one robot around a fixed polygon of waypoints on its pose, for
// recording sequences and benchmarks (`scancrew bench perception`) before the planners
// and the tracker of later steps exist. Not a path planner: it steers straight at the
// next waypoint and does not avoid obstacles, so the waypoints must leave the way free.
//
// Each tick: the current waypoint is reached when within arrive_radius_m (horizontal for
// ground robots), then the next one is taken (from the first again when loop is true).
//   yaw rate  ω = clamp(yaw_gain · e, ±max_yaw_rate), e the heading error to the waypoint
//   ground    v_x = speed · max(0, cos e)       (turns on the spot when facing away)
//   multirotor v = speed · (waypoint − position) / |…| in the body frame, heading as above
// It stops (zero command) after stop_after_m of travel or at the last waypoint.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::waypoint_driver {

class WaypointDriver final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "drives the robot around a fixed loop of waypoints on its pose (recordings, benchmarks)";
  struct Config {
    std::vector<double> waypoints_m;  // x, y, z triples (world frame); z unused for ground robots
    bool loop = true;
    double speed_mps = 0.5;
    double yaw_gain = 1.5;  // 1/s
    double max_yaw_rate_radps = 0.5;
    double arrive_radius_m = 0.5;
    double rate_hz = 10.0;      // command rate
    double stop_after_m = 0.0;  // 0: never (a loop goes on until the run ends)
  };
  static Config read_config(ParamReader& p);

  WaypointDriver(ComponentContext context, Config config);

  double travelled_m() const { return travelled_m_; }
  uint32_t waypoints_reached() const { return reached_; }
  bool stopped() const { return stopped_; }

 private:
  Result<void, std::string> on_configure() override;
  void on_tick();

  Config config_;
  bool ground_ = true;
  Publisher<msg::VelocityCommand> cmd_;
  msg::Odometry pose_;
  bool have_pose_ = false, have_last_ = false, stopped_ = false;
  msg::Vec3 last_position_;
  size_t target_ = 0;
  uint32_t reached_ = 0;
  double travelled_m_ = 0;
};

}  // namespace scancrew::waypoint_driver
