#pragma once

// The YAML side of ParamReader, for the launch loader only (includes yaml-cpp).

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/result.hpp"
#include "executors/params.hpp"

namespace scancrew {

struct ParamReader::Impl {
  YAML::Node node;   // a mapping, or null/undefined for "no parameters"
  std::string file;  // the launch file
  std::string path;  // e.g. "components[2].params"
  // replaced in every string read (a per-robot component's "{ns}", "{id}")
  std::vector<std::pair<std::string, std::string>> substitutions;
};

// `text` with every `from` of `substitutions` replaced by its `to`.
std::string substitute(std::string text,
                       const std::vector<std::pair<std::string, std::string>>& substitutions);

// "file:line" of a node (line 1-based), or just the file when the node has no mark.
std::string yaml_location(const std::string& file, const YAML::Node& node);

// Parses YAML text; the error names the label (a file) and line.
Result<YAML::Node, std::string> parse_yaml(const std::string& text, const std::string& label);
// The largest text file read_text_file() reads (launch, scene, profile, calibration files and
// run-directory JSON are kilobytes to a few megabytes).
inline constexpr uintmax_t kMaxTextFileBytes = uintmax_t{64} << 20;
// The whole file, or why not: it cannot be opened, is not a regular file (a device such as
// /dev/zero, a pipe, a directory) or is over kMaxTextFileBytes.
Result<std::string, std::string> read_text_file(const std::string& path);

// Applies `--set name.key=value` overrides onto a launch file's tree (a component's params,
// or the run / executor / security section) before it is read; the errors, one per bad one.
// `clock=wall` runs the launch on the wall clock: a step executor becomes multi_threaded
// (a thread per core) and the sim-time run: keys (compute_time, real_time_factor,
// sim_step_s) are dropped; --set of one of those, or of executor.type=step, is refused.
std::vector<std::string> apply_launch_overrides(YAML::Node& root,
                                                const std::vector<std::string>& overrides,
                                                const std::string& file);

ParamReader make_param_reader(const YAML::Node& node, const std::string& file,
                              const std::string& path,
                              std::vector<std::pair<std::string, std::string>> substitutions = {});

}  // namespace scancrew
