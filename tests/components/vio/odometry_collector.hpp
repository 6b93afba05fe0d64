#pragma once
// The VIO tests' collector (test_vio, test_vio_mission): keeps every odometry and ground-truth
// pose of its robot. Registered once, as "test_vio_collector", in test_vio.cpp.

#include <utility>
#include <vector>

#include "executors/component.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::vio::testing {

class Collector final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps odom and pose_gt";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  Collector(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  std::vector<msg::Odometry> odom, truth;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::Odometry>("odom", {.depth = 8},
                                       [this](Sample<msg::Odometry>&& s) { odom.push_back(*s); });
    create_subscription<msg::Odometry>("pose_gt", {.depth = 8},
                                       [this](Sample<msg::Odometry>&& s) { truth.push_back(*s); });
    return {};
  }
};

}  // namespace scancrew::vio::testing
