#pragma once

// ConstantDriver: a test component that sends a constant body-frame velocity command
// (vx, yaw_rate) on cmd_vel every 0.1 s. Registered as "test_constant_driver"; include this
// header in one source file per test executable.

#include <chrono>
#include <string_view>

#include "executors/component.hpp"
#include "executors/params.hpp"
#include "executors/registry.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::test {

class ConstantDriver final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: constant cmd_vel";
  struct Config {
    double vx = 0, yaw_rate = 0;
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional("vx", c.vx);
    p.optional("yaw_rate", c.yaw_rate);
    return c;
  }
  ConstantDriver(ComponentContext c, Config config) : Component(std::move(c)), config_(config) {}

 private:
  Result<void, std::string> on_configure() override {
    pub_ = create_publisher<msg::VelocityCommand>("cmd_vel");
    create_timer(std::chrono::milliseconds(100), [this] {
      auto loan = pub_.loan();
      if (!loan) return;
      (*loan)->linear_mps = {config_.vx, 0, 0};
      (*loan)->yaw_rate_radps = config_.yaw_rate;
      (void)pub_.publish(std::move(*loan));
    });
    return {};
  }
  Config config_;
  Publisher<msg::VelocityCommand> pub_;
};

SCANCREW_REGISTER_COMPONENT(ConstantDriver, "test_constant_driver")

}  // namespace scancrew::test
