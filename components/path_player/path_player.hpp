#pragma once

// PathPlayer: a stand-in for the low-level planner in tests and demos — publishes one
// fixed LocalPath, given in its parameters, so the path tracker can be run alone
// (launch_cfg/tracker_sim.yaml). Not a planner: the path is sent as given, with no
// collision check.
//
// Parameters
//   waypoints   x, y, z (m), yaw (deg) quadruples, world frame, at least one
//   plan_id     the plan id the path carries (default 1)
//   start_s     first sent at this time on the launch's clock (default 0)
//   period_s    then sent again every period_s, unchanged (a late subscriber gets it;
//               the tracker ignores an unchanged re-send); 0: sent once
// Port: out local_path (msg::LocalPath).

#include <cstdint>
#include <string_view>
#include <vector>

#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::path_player {

class PathPlayer final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "publishes a fixed local path from its parameters (tests and demos of the tracker)";
  struct Config {
    std::vector<msg::Waypoint> waypoints;
    uint64_t plan_id = 1;
    double start_s = 0.0;
    double period_s = 1.0;
  };
  static Config read_config(ParamReader& p);

  PathPlayer(ComponentContext context, Config config);

  uint32_t sent() const { return sent_; }

 private:
  Result<void, std::string> on_configure() override;
  void on_tick();

  Config config_;
  Publisher<msg::LocalPath> path_;
  int64_t next_ns_ = 0;
  uint32_t sent_ = 0;
};

}  // namespace scancrew::path_player
