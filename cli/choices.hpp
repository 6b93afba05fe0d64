#pragma once

// The choices the commands of cli/ name in files, options and tables, as enums with their
// names (core/enum_names.hpp): a team's architecture, its depth and pose sources and how a
// mission run ended. Parsed with value_of (the errors list joined_names), printed with
// name_of / to_string, so that launch files, run directories, CSV, JSON and Markdown spell
// them as before.

#include <cstdint>
#include <string>
#include <vector>

#include "core/enum_names.hpp"

namespace scancrew::cli {

// "a, b, c": the names of a table, for an error that lists the allowed values.
template <class E, size_t N>
std::string joined_names(const EnumNames<E, N>& names) {
  std::string s;
  for (const auto& n : names) {
    if (!s.empty()) s += ", ";
    s += n.name;
  }
  return s;
}

// The names of a table as strings (CLI::IsMember).
template <class E, size_t N>
std::vector<std::string> name_list(const EnumNames<E, N>& names) {
  std::vector<std::string> list;
  list.reserve(N);
  for (const auto& n : names) list.emplace_back(n.name);
  return list;
}

// A team's architecture (cli/mission_compose.hpp): one robot alone, its map, ISEs and plans
// on board (single); a ground station that maps, extracts ISEs and runs TSGA for the team
// (centralized); each robot mapping patches and running dist-TSGA (distributed). In the order
// a sweep and the benchmark run them.
enum class Architecture : uint8_t { kSingle, kCentralized, kDistributed };

inline constexpr EnumNames<Architecture, 3> kArchitectureNames = {
    {{Architecture::kSingle, "single"},
     {Architecture::kCentralized, "centralized"},
     {Architecture::kDistributed, "distributed"}}};

inline std::string to_string(Architecture arch) {
  return std::string(name_of(kArchitectureNames, arch));
}

// Where a composed mission's depth comes from (mission file `depth:`): the simulator's
// rendered, noisy depth (rendered), or SGBM matching on each robot's stereo pair, the
// `stereo_depth` component (stereo), as on the thesis's real robots (Table 5.4).
enum class DepthSource : uint8_t { kRendered, kStereo };

inline constexpr EnumNames<DepthSource, 2> kDepthSourceNames = {
    {{DepthSource::kRendered, "rendered"}, {DepthSource::kStereo, "stereo"}}};

inline std::string to_string(DepthSource d) {
  return std::string(name_of(kDepthSourceNames, d));
}

// Where a composed mission's robot poses come from (mission file `pose:`): the simulator's
// ground truth (truth), or each robot's visual-inertial odometry, the `vio` component (vio).
enum class PoseSource : uint8_t { kTruth, kVio };

inline constexpr EnumNames<PoseSource, 2> kPoseSourceNames = {
    {{PoseSource::kTruth, "truth"}, {PoseSource::kVio, "vio"}}};

inline std::string to_string(PoseSource p) {
  return std::string(name_of(kPoseSourceNames, p));
}

// How a mission run ended (metrics.json's stop_reason): the mission monitor's complete or
// stalled, the run's time_budget or interrupted (Ctrl-C), and, for a sweep or the benchmark,
// failed: no metrics.json to read.
enum class StopReason : uint8_t { kComplete, kStalled, kTimeBudget, kInterrupted, kFailed };

inline constexpr EnumNames<StopReason, 5> kStopReasonNames = {
    {{StopReason::kComplete, "complete"},
     {StopReason::kStalled, "stalled"},
     {StopReason::kTimeBudget, "time_budget"},
     {StopReason::kInterrupted, "interrupted"},
     {StopReason::kFailed, "failed"}}};

inline std::string to_string(StopReason reason) {
  return std::string(name_of(kStopReasonNames, reason));
}

}  // namespace scancrew::cli
