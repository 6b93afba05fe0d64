#pragma once

// The parameter reference: each registered component type's parameters as its read_config()
// asks for them (ComponentRegistry::parameters), as text (`scancrew components NAME`) or as
// the Markdown of docs/parameters.md (`scancrew components --markdown`).

#include <string>
#include <vector>

#include "executors/params.hpp"

namespace scancrew::cli {

// "type: description", then one aligned line per parameter: key, type, default ("(required)"
// for a required one), range or allowed names, description ("(no description)" if none).
std::string parameter_text(const std::string& type, const std::string& description,
                           const std::vector<ParamInfo>& parameters);

// docs/parameters.md: a section with a table per registered component type.
std::string parameters_markdown();

}  // namespace scancrew::cli
