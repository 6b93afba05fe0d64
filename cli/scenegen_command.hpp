#pragma once

// `scancrew scenegen --family indoor|outdoor --seed N --out DIR`: a procedural scene
// (scenegen/scenegen.hpp, docs/scenegen.md) written as DIR/<family>_<seed>.yaml, with a
// one-line summary. Bad input (no or unknown family, no or bad seed, no output folder):
// a message and exit status 2.

#include <string>

namespace scancrew::cli {

struct ScenegenOptions {
  std::string family;  // "indoor" | "outdoor"
  std::string seed;    // a non-negative integer, parsed by run_scenegen (to name what is wrong)
  std::string out_dir;
};

int run_scenegen(const ScenegenOptions& options);

}  // namespace scancrew::cli
