#include "core/motion/utility_check.hpp"

#include <algorithm>

namespace scancrew::motion {

UtilityStatus utility_check(size_t start_count, size_t left_count,
                            const UtilityCheckConfig& config) {
  UtilityStatus s;
  if (start_count == 0) return s;
  const size_t left = std::min(left_count, start_count);
  s.completed_fraction = static_cast<double>(start_count - left) / static_cast<double>(start_count);
  // c_thres of the initial ISEs done; a tiny epsilon so 4 of 5 done meets 80 %
  s.update = s.completed_fraction * 100.0 >= config.c_thres_percent - 1e-9;
  return s;
}

size_t count_remaining(std::span<const uint64_t> start_ids, std::span<const uint64_t> current_ids) {
  size_t n = 0;
  auto c = current_ids.begin();
  for (const uint64_t id : start_ids) {
    c = std::lower_bound(c, current_ids.end(), id);
    if (c == current_ids.end()) break;
    if (*c == id) ++n;
  }
  return n;
}

}  // namespace scancrew::motion
