#pragma once

// What this scancrew binary is: its version (CMake's project version), the git commit it was
// built from (`git describe --always --dirty` at build time, "unknown" outside a git
// checkout: cli/git_commit.cmake) and the versions of the libraries it was built with (their
// headers' version macros, or CMake's find_package version where a library has none).
// `scancrew --version` prints them; every run directory keeps them in run.json.

#include <string>
#include <vector>

namespace scancrew::cli {

struct Dependency {
  std::string name;
  std::string version;
};

std::string scancrew_version();
std::string git_commit();
std::vector<Dependency> dependency_versions();

// `scancrew --version`: "scancrew 0.1.0 (commit 5130d07)", then one "  name version" line
// per library.
std::string version_text();

}  // namespace scancrew::cli
