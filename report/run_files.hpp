#pragma once

// The files of a mission's run directory that the mission monitor writes while it runs and
// the report reads afterwards (docs/missions.md lists them all):
//   paths.csv     t_s,robot_id,x_m,y_m,z_m,yaw_rad      each robot's ground-truth pose over time
//   coverage.csv  t_s,robot_id,coverage,coverage_reachable,ises_left
//                 the share of the scene's surface each robot's map has seen, of all of it and
//                 of what its team's robot kinds can observe (-1: not measured), its ISEs left
// Rows are in time order; a robot's rows need not be contiguous. Numbers are written with
// enough digits to read back what was written (positions to 0.1 mm, times to 1 ms).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace scancrew::report {

struct PathSample {
  double t_s = 0;
  uint32_t robot_id = 0;
  double x_m = 0, y_m = 0, z_m = 0, yaw_rad = 0;
};

struct CoverageSample {
  double t_s = 0;
  uint32_t robot_id = 0;
  double coverage = 0;             // [0, 1]
  double coverage_reachable = -1;  // [0, 1] of the reachable ground truth; -1: not measured
  uint64_t ises_left = 0;          // ISEs of the robot's latest ISE update
};

// The first time the team's coverage (the best robot's at each sample time) reaches
// `share` (of all the ground truth, or of the reachable part), if it does.
std::optional<double> time_to_coverage(const std::vector<CoverageSample>& samples, double share,
                                       bool reachable);

// Writers fail with the file name and the cause (cannot open, write failed).
Result<void, std::string> write_paths_csv(const std::string& path,
                                          const std::vector<PathSample>& samples);
Result<void, std::string> write_coverage_csv(const std::string& path,
                                             const std::vector<CoverageSample>& samples);
// Readers check the header and every field; an error names the file, the line and the field.
Result<std::vector<PathSample>, std::string> read_paths_csv(const std::string& path);
Result<std::vector<CoverageSample>, std::string> read_coverage_csv(const std::string& path);

}  // namespace scancrew::report
