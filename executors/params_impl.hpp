#pragma once

// The YAML side of ParamReader, for the launch loader only (includes yaml-cpp).

#include <yaml-cpp/yaml.h>

#include <string>

#include "executors/params.hpp"

namespace scancrew {

struct ParamReader::Impl {
  YAML::Node node;   // a mapping, or null/undefined for "no parameters"
  std::string file;  // the launch file
  std::string path;  // e.g. "components[2].params"
};

// "file:line" of a node (line 1-based), or just the file when the node has no mark.
std::string yaml_location(const std::string& file, const YAML::Node& node);

ParamReader make_param_reader(const YAML::Node& node, const std::string& file,
                              const std::string& path);

}  // namespace scancrew
