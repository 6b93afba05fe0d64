// The launch tests' harness (launch_harness.hpp): registers test_named once for the test
// executable.

#include "tests/executors/launch_harness.hpp"

#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::test {

SCANCREW_REGISTER_COMPONENT(Named, "test_named")

std::string errors_of(const std::string& text) {
  auto launch = Launch::from_string(text, "bad.yaml");
  if (launch) return "";
  std::string all;
  for (const auto& e : launch.error()) all += e + "\n";
  return all;
}

}  // namespace scancrew::test
