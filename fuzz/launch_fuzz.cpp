// Launch files (executors/launch.hpp): the YAML parser with its limits (duplicate keys, alias
// expansion) and the launch description (settings, robots, remaps, components; no component
// type is registered in this harness, so each is an "unknown component" error).
#include <string>

#include "executors/launch.hpp"
#include "fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)scancrew::Launch::from_string(text, "fuzz.yaml");
  return 0;
}
