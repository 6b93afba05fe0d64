#pragma once

// What a run directory keeps to repeat the run (docs/missions.md, "Repeating a run"):
//   launch.resolved.yaml: the launch file as the run composed it (a mission file's composed
//     graph), with the run's --set overrides applied; "{out}" is left for the run directory,
//     and the relative paths of the input files it read are made absolute. Parameters the
//     file leaves out took their component's defaults (not written out).
//   run.json: the command (argv, shell-quoted) and its working directory, the launch file and
//     the --set overrides as given, --robots and --trace-events, the seeds the resolved file
//     sets, and the scancrew version, git commit and library versions (cli/build_info.hpp).
// `scancrew rerun DIR` (cli/rerun_command.cpp) runs launch.resolved.yaml again from them.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/run_command.hpp"
#include "core/result.hpp"

namespace scancrew::cli {

inline constexpr const char* kResolvedLaunchFile = "launch.resolved.yaml";
inline constexpr const char* kRunRecordFile = "run.json";

// The process's command line as given (main() sets it); empty until set.
void set_command_line(int argc, const char* const* argv);
const std::vector<std::string>& command_line();

// The words as a POSIX shell reads them back: a word of safe characters as it is, any other
// in single quotes ('it'\''s'); words separated by one space.
std::string shell_quoted(const std::vector<std::string>& words);

// The launch file at `path` as `scancrew run` composes it (a mission file with `robots`
// robots, 0: as it says), with `overrides` (--set) applied, as YAML text; or why not.
Result<std::string, std::string> resolved_launch_text(const std::string& path, size_t robots,
                                                      const std::vector<std::string>& overrides);

// Writes launch.resolved.yaml and run.json into `out` for the run `options` describe; false
// after saying why not.
bool write_run_record(const std::filesystem::path& out, const RunOptions& options);

}  // namespace scancrew::cli
