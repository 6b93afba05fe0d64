#pragma once

// The report of a mission run directory (docs/missions.md): from metrics.json, paths.csv,
// coverage.csv, mesh.ply and ises*.ply it writes top_view.png, coverage.png and report.html,
// a self-contained page (inline CSS, the 3D view's script and scene inlined: no external
// links, so it opens offline; report/scene_view.hpp) with the mission's
// metrics (the thesis' evaluation quantities, 5.4: coverage, reconstruction error,
// completion time, path length, data exchanged), a table per robot, the compute time per
// component, the two pictures and links to the files of the directory.

#include <string>

#include "core/result.hpp"

namespace scancrew::report {

// metrics.json is required: a missing or malformed one is an error naming it. Every other
// input is optional: a missing file or key shows as "—"; an optional file that cannot be
// read is named in the report's notes and left out of the pictures. Errors also name an
// output that cannot be written. Strings from the files are HTML-escaped.
Result<void, std::string> write_report(const std::string& run_dir);

}  // namespace scancrew::report
