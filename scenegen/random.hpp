#pragma once

// Rng: the one random stream of a generated scene. std::mt19937_64's output is fixed by
// the standard, but std::uniform_*_distribution's is not (libstdc++ and libc++ differ), so
// the draws are made here from the raw 64-bit words: same seed, same scene, whatever the
// standard library. Not thread safe; allocates nothing.

#include <cmath>
#include <cstdint>
#include <random>

namespace scancrew::scenegen {

class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}

  // in [0, 1), 53 random bits
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  // in [lo, hi)
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  // in [lo, hi], both included (the modulo bias of 64-bit words is negligible here)
  int integer(int lo, int hi) {
    return lo + static_cast<int>(engine_() % static_cast<uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return unit() < p; }
  // a fresh stream for a sub-task (a redraw), fixed by this stream's next word
  uint64_t fork() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

// x rounded to the centimetre, for drawn sizes and positions (the scene file is written to
// the millimetre, so a centimetre grid reads back exactly as drawn, halves included)
inline double cm(double x) {
  return std::round(x * 100.0) / 100.0;
}

}  // namespace scancrew::scenegen
