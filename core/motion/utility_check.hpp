#pragma once

// UtilityCheck (thesis 2.5.3 item 3; Algorithm 1 line 5, Algorithm 3 line 5, Algorithm 6
// line 9): the robot stops and waits for a new tour once c_thres of the ISEs the tour was
// planned for (C_start, taken when the tour arrived) are completed. c_thres is 80 % in
// tables 2.1, 3.1 and 4.1 (Powerplant), 50 % for SoL. Pure functions, any thread.

#include <cstddef>
#include <cstdint>
#include <span>

namespace scancrew::motion {

struct UtilityCheckConfig {
  double c_thres_percent = 80.0;  // tables 2.1, 3.1, 4.1 (Powerplant); 50 for SoL
};

struct UtilityStatus {
  bool update = false;              // wait for high-level re-planning
  double completed_fraction = 0.0;  // (|C_start| - |C_left|) / |C_start|, 0 when C_start is empty
};

// UtilityCheck(C_start, C): `start_count` = |C_start|, `left_count` = how many of those are
// still ISEs. An empty C_start never asks for an update (the thesis is silent: a tour that
// scans nothing would otherwise be replanned at once, forever). left > start is clamped.
UtilityStatus utility_check(size_t start_count, size_t left_count,
                            const UtilityCheckConfig& config);

// How many ISEs of `start_ids` are still in `current_ids` (both sorted ascending, no
// duplicates; the ids are the caller's, e.g. packed voxel indices). O(|start| log |current|)
// at most, no allocation.
size_t count_remaining(std::span<const uint64_t> start_ids, std::span<const uint64_t> current_ids);

}  // namespace scancrew::motion
