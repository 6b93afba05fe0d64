#pragma once

// The report's "Files" table: each file a run directory holds (docs/missions.md), linked,
// with its size and what it holds; the per-robot and per-map files present, by name.

#include <filesystem>
#include <ostream>
#include <string>

namespace scancrew::report {

void file_table(std::ostream& out, const std::filesystem::path& dir);

// "123 B", or "1.5 KiB", "2.0 MiB"... from 1024 B on.
std::string human_bytes(double bytes);

}  // namespace scancrew::report
