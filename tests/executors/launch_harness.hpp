#pragma once

// The launch tests' harness: a component that keeps the string parameters the launch file
// handed it (registered as "test_named" in launch_harness.cpp), and a launch file's errors
// as one string.

#include <string>
#include <string_view>
#include <vector>

#include "executors/component.hpp"
#include "executors/params.hpp"

namespace scancrew::test {

// Keeps its string parameters, to check what the launch file handed it.
class Named final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps its label parameters";
  struct Config {
    std::string label;
    std::vector<std::string> labels;
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional("label", c.label);
    p.optional_list("labels", c.labels);
    return c;
  }
  Named(ComponentContext c, Config config) : Component(std::move(c)), config_(std::move(config)) {}
  const Config& config() const { return config_; }
  // its label as an input file's path (Component::input_path)
  std::string label_path() const { return input_path("label", config_.label); }

 private:
  Result<void, std::string> on_configure() override { return {}; }
  Config config_;
};

// Every error of a launch from text (file name "bad.yaml"), one a line; "" when it composes.
std::string errors_of(const std::string& text);

}  // namespace scancrew::test
