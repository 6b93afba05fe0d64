// The report's table of the run directory's files (report/run_files_table.hpp).

#include "report/run_files_table.hpp"

#include <algorithm>
#include <cstdio>
#include <string_view>
#include <vector>

#include "core/markup_escape.hpp"

namespace scancrew::report {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMissing = "&mdash;";

std::string printf_string(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

struct RunFile {
  const char* name;
  const char* what;
};

constexpr RunFile kRunFiles[] = {
    {"mesh.ply", "the reconstruction, a triangle mesh (PLY)"},
    {"map.bt", "the team's map as an OctoMap (open with octovis)"},
    {"paths.csv", "each robot's pose over time: t_s,robot_id,x_m,y_m,z_m,yaw_rad"},
    {"coverage.csv",
     "each robot's coverage and ISEs left over time: t_s,robot_id,coverage,"
     "ises_left"},
    {"metrics.json", "the mission's metrics (the tables above)"},
    {"trace.json", "the execution trace: open trace.json in https://ui.perfetto.dev"},
    {"launch.resolved.yaml", "the launch file as the run composed it, its --set overrides applied"},
    {"run.json",
     "the command, working directory, seeds and versions: scancrew rerun DIR repeats it"},
};

// Files a run writes per robot or per map, by name: prefix, suffix, what they hold.
struct RunFilePattern {
  const char* prefix;
  const char* suffix;
  const char* what;
};

constexpr RunFilePattern kRunFilePatterns[] = {
    {"mesh_", ".ply", "one robot's or one map's own mesh (PLY)"},
    {"map_", ".bt", "one robot's map as an OctoMap"},
    {"ises_", ".ply", "the ISEs left at the end (PLY points)"},
    {"topics.txt", "", "each topic: messages, rate per second of the run's clock, latency"},
};

void file_row(std::ostream& out, const fs::path& dir, const std::string& name, const char* what) {
  std::error_code ec;
  const fs::path p = dir / name;
  const bool present = fs::is_regular_file(p, ec);
  const auto size = present ? fs::file_size(p, ec) : 0;
  out << "<tr><td>";
  if (present)
    out << "<a href=\"" << markup_escape(name) << "\">" << markup_escape(name) << "</a>";
  else
    out << markup_escape(name);
  out << "</td><td class=\"n\">"
      << (present && !ec ? human_bytes(static_cast<double>(size)) : kMissing) << "</td><td>"
      << markup_escape(what) << "</td></tr>\n";
}

}  // namespace

void file_table(std::ostream& out, const fs::path& dir) {
  out << "<h2>Files</h2>\n<table>\n<tr><th>File</th><th>Size</th><th>Holds</th></tr>\n";
  for (const RunFile& f : kRunFiles) file_row(out, dir, f.name, f.what);
  // the per-robot and per-map files present, in name order
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) names.push_back(it->path().filename().string());
  std::sort(names.begin(), names.end());
  for (const RunFilePattern& pattern : kRunFilePatterns)
    for (const std::string& name : names) {
      const std::string_view n(name), prefix(pattern.prefix), suffix(pattern.suffix);
      if (n.size() >= prefix.size() + suffix.size() && n.substr(0, prefix.size()) == prefix &&
          n.substr(n.size() - suffix.size()) == suffix)
        file_row(out, dir, name, pattern.what);
    }
  out << "</table>\n";
}

std::string human_bytes(double bytes) {
  static constexpr const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB"};
  std::string s = printf_string("%.0f B", bytes);
  double v = bytes;
  for (const char* unit : kUnits) {
    if (v < 1024) break;
    v /= 1024;
    s = printf_string("%.1f ", v) + unit;
  }
  return s;
}

}  // namespace scancrew::report
