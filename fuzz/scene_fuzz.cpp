// Scene files (sim/scene.hpp): bounds, solids, meshes (file names are only looked up),
// robots' starts.
#include <string>

#include "fuzz/fuzz_input.hpp"
#include "sim/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)scancrew::sim::parse_scene(text, "fuzz_scene.yaml", "/nonexistent");
  return 0;
}
