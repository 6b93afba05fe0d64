#include "report/run_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/io/ply.hpp"
#include "core/markup_escape.hpp"
#include "executors/params_impl.hpp"
#include "report/plots.hpp"
#include "report/run_files.hpp"
#include "report/run_files_table.hpp"
#include "report/scene_view.hpp"
#include "report/time_breakdown.hpp"

namespace scancrew::report {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr const char* kMissing = "&mdash;";

// kMillis: 3 significant digits (a 4 µs callback is 0.004 ms, not 0.00)
enum class Format { kText, kBool, kInteger, kFixed1, kFixed2, kFixed4, kPercent, kBytes, kMillis };

std::string printf_string(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// The HTML of a value of the metrics, or "—" when absent or null. A value of an unexpected
// type is shown as its JSON text.
std::string cell(const Json& object, const char* key, Format format) {
  if (!object.is_object() || !object.contains(key) || object.at(key).is_null()) return kMissing;
  const Json& v = object.at(key);
  if (v.is_string()) return markup_escape(v.get<std::string>());
  if (format == Format::kBool && v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (!v.is_number() || format == Format::kText || format == Format::kBool)
    return markup_escape(v.dump(-1, ' ', false, Json::error_handler_t::replace));
  const double x = v.get<double>();
  switch (format) {
    case Format::kInteger:
      return printf_string("%.0f", x);
    case Format::kFixed1:
      return printf_string("%.1f", x);
    case Format::kFixed2:
      return printf_string("%.2f", x);
    case Format::kFixed4:
      return printf_string("%.4f", x);
    case Format::kMillis:
      return printf_string("%.3g", x);
    case Format::kPercent:
      return printf_string("%.1f", 100 * x);
    case Format::kBytes:
      return x >= 1024 ? printf_string("%.0f B", x) + " (" + human_bytes(x) + ")"
                       : printf_string("%.0f B", x);
    default:
      return markup_escape(v.dump());
  }
}

std::string colour_hex(uint32_t robot_id) {
  const auto rgb = robot_colour_rgb(robot_id);
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return buf;
}

constexpr const char* kCss = R"(
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:2em auto;
max-width:1100px;padding:0 1em;color:#222;line-height:1.4}
h1{font-size:1.6em;margin-bottom:.2em}h2{font-size:1.25em;margin-top:1.6em;
border-bottom:1px solid #ddd;padding-bottom:.2em}
.sub{color:#666;margin-top:0}
table{border-collapse:collapse;margin:.5em 0}
th,td{border:1px solid #ddd;padding:.3em .7em;text-align:left}
th{background:#f4f4f4}td.n{text-align:right;font-variant-numeric:tabular-nums}
.sw{display:inline-block;width:.9em;height:.9em;border-radius:2px;margin-right:.4em;
vertical-align:-.1em}
figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}
figcaption{color:#555;font-size:.9em}
.note{background:#fff6e0;border-left:4px solid #e0a000;padding:.4em .8em}
code{background:#f4f4f4;padding:0 .25em}
.bar{display:flex;width:420px;height:1.1em;border:1px solid #ccc}.bar span{height:100%}
.small{font-size:.8em;color:#555}.legend{font-size:.9em}
)";

struct Row {
  const char* label;
  const char* key;
  Format format;
  const char* parent = nullptr;  // the key of the object that holds key; nullptr: the top
};

constexpr Row kSummary[] = {
    {"Launch file", "launch", Format::kText},
    {"Scene", "scene", Format::kText},
    {"Architecture", "architecture", Format::kText},
    {"Started", "started", Format::kText},
    {"Completed", "completed", Format::kBool},
    {"Stop reason", "stop_reason", Format::kText},
    {"Completion time (s)", "completion_time_s", Format::kFixed1},
    {"Simulated time (s)", "sim_time_s", Format::kFixed1},
    {"Wall-clock time (s)", "wall_time_s", Format::kFixed1},
    {"Real-time factor", "real_time_factor", Format::kFixed2},
    {"Coverage (%)", "coverage", Format::kPercent},
    {"Evaluation e_max (m)", "eval_e_max_m", Format::kFixed4},
    {"Mean error (m)", "mean_error_m", Format::kFixed4},
    {"Error std. dev. (m)", "std_error_m", Format::kFixed4},
    {"RMSE (m)", "rmse_m", Format::kFixed4},
    {"Total path length (m)", "total_path_length_m", Format::kFixed1},
    {"Data exchanged", "data_exchanged_bytes", Format::kBytes},
    {"Mesh scored (from)", "mesh_from", Format::kText},
    {"Collisions", "collisions", Format::kInteger},
    {"Contacts robot-robot", "robot_robot", Format::kInteger, "contacts"},
    {"Contacts robot-scene", "robot_scene", Format::kInteger, "contacts"},
    {"Replans", "replans", Format::kInteger},
    {"Compute time", "compute_time", Format::kText},
    {"Coverage of the reachable surface (%)", "coverage_reachable", Format::kPercent},
    {"Time to 90 % coverage (s)", "90", Format::kFixed1, "time_to_coverage_s"},
    {"Time to 95 % coverage (s)", "95", Format::kFixed1, "time_to_coverage_s"},
    {"Time to 90 % of the reachable (s)", "90", Format::kFixed1, "time_to_coverage_reachable_s"},
    {"Time to 95 % of the reachable (s)", "95", Format::kFixed1, "time_to_coverage_reachable_s"},
    {"Idle share (%)", "idle_share", Format::kPercent},
    {"Tours per goal reached", "tours_per_goal", Format::kFixed2},
    {"Metres per goal reached", "m_per_goal", Format::kFixed2},
};

constexpr Row kRobotColumns[] = {
    {"Namespace", "namespace", Format::kText},
    {"Kind", "kind", Format::kText},
    {"Path length (m)", "path_length_m", Format::kFixed1},
    {"Replans", "replans", Format::kInteger},
    {"Coverage (%)", "coverage", Format::kPercent},
    {"Goals reached", "goals_reached", Format::kInteger},
    {"State", "state", Format::kText},
};

bool is_numeric(Format f) {
  return f != Format::kText && f != Format::kBool;
}

void summary_table(std::ostream& out, const Json& metrics) {
  out << "<h2>Mission</h2>\n<table>\n";
  for (const Row& r : kSummary) {
    static const Json null_json;
    const Json* holder = &metrics;
    if (r.parent != nullptr)
      holder = metrics.contains(r.parent) ? &metrics.at(r.parent) : &null_json;
    // a robot alone exchanges nothing: "0 B" would read as a broken link
    const bool alone = std::string_view(r.key) == "data_exchanged_bytes" &&
                       metrics.contains("robots") && metrics.at("robots").is_array() &&
                       metrics.at("robots").size() <= 1;
    out << "<tr><th>" << r.label << "</th><td" << (is_numeric(r.format) ? " class=\"n\"" : "")
        << ">"
        << (alone ? std::string("&mdash; (one robot: nothing to exchange)")
                  : cell(*holder, r.key, r.format))
        << "</td></tr>\n";
  }
  out << "</table>\n";
}

// Per robot: the metrics' robots[]; its ISEs left, or else those of the robot's last row of
// coverage.csv.
void robot_table(std::ostream& out, const Json& metrics,
                 const std::map<uint32_t, uint64_t>& last_ises) {
  out << "<h2>Robots</h2>\n";
  const Json* robots = metrics.contains("robots") ? &metrics.at("robots") : nullptr;
  if (robots == nullptr || !robots->is_array() || robots->empty()) {
    out << "<p>" << kMissing << " (no per-robot metrics)</p>\n";
    return;
  }
  out << "<table>\n<tr><th>Robot</th>";
  for (const Row& c : kRobotColumns) out << "<th>" << c.label << "</th>";
  out << "<th>ISEs left</th></tr>\n";
  for (const Json& robot : *robots) {
    out << "<tr><td>";
    const bool has_id = robot.is_object() && robot.contains("id") &&
                        robot.at("id").is_number_unsigned() &&
                        robot.at("id").get<uint64_t>() <= UINT32_MAX;
    std::string ises = cell(robot, "ises_left", Format::kInteger);
    if (has_id) {
      const auto id = robot.at("id").get<uint32_t>();
      out << "<span class=\"sw\" style=\"background:" << colour_hex(id) << "\"></span>";
      if (const auto it = last_ises.find(id); it != last_ises.end() && ises == kMissing)
        ises = std::to_string(it->second);
    }
    out << cell(robot, "id", Format::kInteger) << "</td>";
    for (const Row& c : kRobotColumns)
      out << "<td" << (is_numeric(c.format) ? " class=\"n\"" : "") << ">"
          << cell(robot, c.key, c.format) << "</td>";
    out << "<td class=\"n\">" << ises << "</td></tr>\n";
  }
  out << "</table>\n";
}

// Per robot, a bar split by where its mission time went (metrics' robots[].time_s).
void time_bars(std::ostream& out, const Json& metrics) {
  out << "<h2>Where the time goes</h2>\n";
  const Json* robots = metrics.contains("robots") ? &metrics.at("robots") : nullptr;
  bool any = false;
  if (robots != nullptr && robots->is_array())
    for (const Json& r : *robots) any = any || (r.is_object() && r.contains("time_s"));
  if (!any) {
    out << "<p>" << kMissing << " (no time breakdown in metrics.json)</p>\n";
    return;
  }
  // one colour per activity, in report::Activity's order
  static constexpr std::array<const char*, report::kActivityCount> kColours = {
      "#4e79a7", "#76b7b2", "#f28e2b", "#e15759", "#b07aa1", "#edc948", "#59a14f", "#9c755f"};
  out << "<p class=\"legend\">";
  for (size_t a = 0; a < report::kActivityCount; ++a)
    out << "<span class=\"sw\" style=\"background:" << kColours[a] << "\"></span>"
        << markup_escape(std::string(report::label(static_cast<report::Activity>(a)))) << " ";
  out << "</p>\n<table class=\"bars\">\n";
  for (const Json& r : *robots) {
    if (!r.is_object() || !r.contains("time_s") || !r.at("time_s").is_object()) continue;
    const Json& t = r.at("time_s");
    double total = 0;
    for (const auto& [k, v] : t.items()) total += v.is_number() ? v.get<double>() : 0;
    out << "<tr><th>" << markup_escape(cell(r, "namespace", Format::kText)) << "</th><td>"
        << "<div class=\"bar\">";
    std::string title;
    for (size_t a = 0; a < report::kActivityCount; ++a) {
      const auto activity = static_cast<report::Activity>(a);
      const std::string key(report::to_string(activity));
      const double v = t.contains(key) && t.at(key).is_number() ? t.at(key).get<double>() : 0;
      if (total <= 0 || v <= 0) continue;
      char pct[32];
      std::snprintf(pct, sizeof pct, "%.2f", 100 * v / total);
      char what[96];
      std::snprintf(what, sizeof what, "%s: %.1f s (%.0f %%)",
                    std::string(report::label(activity)).c_str(), v, 100 * v / total);
      out << "<span style=\"width:" << pct << "%;background:" << kColours[a] << "\" title=\""
          << markup_escape(what) << "\"></span>";
      title += (title.empty() ? "" : ", ") + std::string(what);
    }
    out << "</div></td><td class=\"small\">" << markup_escape(title) << "</td></tr>\n";
  }
  out << "</table>\n";
}

// Per component: callbacks and times, the most expensive first.
void compute_table(std::ostream& out, const Json& metrics) {
  out << "<h2>Compute time per component</h2>\n";
  const Json* compute = metrics.contains("compute_ms") ? &metrics.at("compute_ms") : nullptr;
  if (compute == nullptr || !compute->is_object() || compute->empty()) {
    out << "<p>" << kMissing << " (no compute times in metrics.json)</p>\n";
    return;
  }
  auto total = [](const Json& c) {
    return c.is_object() && c.contains("total_ms") && c.at("total_ms").is_number()
               ? c.at("total_ms").get<double>()
               : -1.0;
  };
  std::vector<std::pair<std::string, const Json*>> rows;
  rows.reserve(compute->size());
  for (const auto& [name, c] : compute->items()) rows.emplace_back(name, &c);
  std::stable_sort(rows.begin(), rows.end(), [&](const auto& a, const auto& b) {
    return total(*a.second) > total(*b.second);
  });
  out << "<table>\n<tr><th>Component</th><th>Callbacks</th><th>Total (ms)</th>"
         "<th>Mean (ms)</th><th>p50 (ms)</th><th>p99 (ms)</th></tr>\n";
  for (const auto& [name, c] : rows) {
    std::string mean = kMissing;
    if (c->is_object() && c->contains("callbacks") && c->at("callbacks").is_number() &&
        c->at("callbacks").get<double>() > 0 && total(*c) >= 0)
      mean = printf_string("%.3g", total(*c) / c->at("callbacks").get<double>());
    out << "<tr><td>" << markup_escape(name) << "</td><td class=\"n\">"
        << cell(*c, "callbacks", Format::kInteger) << "</td><td class=\"n\">"
        << cell(*c, "total_ms", Format::kFixed1) << "</td><td class=\"n\">" << mean
        << "</td><td class=\"n\">" << cell(*c, "p50_ms", Format::kMillis) << "</td><td class=\"n\">"
        << cell(*c, "p99_ms", Format::kMillis) << "</td></tr>\n";
  }
  out << "</table>\n";
}

// What the pictures show: the optional inputs, each read when present; a file that cannot be
// read adds a note and is left out.
struct PlotInputs {
  io::TriangleMesh mesh;
  std::vector<PathSample> paths;
  std::vector<CoverageSample> coverage;
  std::vector<std::string> notes;
};

PlotInputs read_plot_inputs(const fs::path& dir) {
  PlotInputs in;
  std::error_code ec;
  if (fs::exists(dir / "mesh.ply", ec)) {
    if (auto mesh = io::read_ply_mesh((dir / "mesh.ply").string()))
      in.mesh = std::move(mesh).value();
    else
      in.notes.push_back(mesh.error());
  }
  if (fs::exists(dir / "paths.csv", ec)) {
    if (auto paths = read_paths_csv((dir / "paths.csv").string()))
      in.paths = std::move(paths).value();
    else
      in.notes.push_back(paths.error());
  }
  if (fs::exists(dir / "coverage.csv", ec)) {
    if (auto coverage = read_coverage_csv((dir / "coverage.csv").string()))
      in.coverage = std::move(coverage).value();
    else
      in.notes.push_back(coverage.error());
  }
  return in;
}

// The metrics' robots (robots[]: id, namespace, patch_bytes_sent) for the 3D view.
std::vector<SceneRobot> scene_robots(const Json& metrics) {
  std::vector<SceneRobot> robots;
  if (!metrics.contains("robots") || !metrics.at("robots").is_array()) return robots;
  for (const Json& r : metrics.at("robots")) {
    if (!r.is_object() || !r.contains("id") || !r.at("id").is_number_unsigned() ||
        r.at("id").get<uint64_t>() > UINT32_MAX)
      continue;
    SceneRobot robot{.id = r.at("id").get<uint32_t>()};
    if (r.contains("namespace") && r.at("namespace").is_string())
      robot.name = r.at("namespace").get<std::string>();
    if (r.contains("patch_bytes_sent") && r.at("patch_bytes_sent").is_number_unsigned())
      robot.bytes_sent = r.at("patch_bytes_sent").get<uint64_t>();
    robots.push_back(std::move(robot));
  }
  return robots;
}

std::string string_or(const Json& metrics, const char* key, const std::string& fallback) {
  return metrics.contains(key) && metrics.at(key).is_string() ? metrics.at(key).get<std::string>()
                                                              : fallback;
}

}  // namespace

Result<void, std::string> write_report(const std::string& run_dir) {
  const fs::path dir(run_dir);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    return make_unexpected("run directory '" + run_dir + "' does not exist");
  const fs::path metrics_path = dir / "metrics.json";
  const auto metrics_text = read_text_file(metrics_path.string());
  if (!metrics_text)
    return make_unexpected("run directory '" + run_dir + "' has no readable metrics.json ('" +
                           metrics_path.string() + "': " + metrics_text.error() + ")");
  Json metrics;
  try {
    metrics = Json::parse(*metrics_text);
  } catch (const Json::exception& e) {
    return make_unexpected("metrics file '" + metrics_path.string() + "': " + e.what());
  }
  if (!metrics.is_object())
    return make_unexpected("metrics file '" + metrics_path.string() + "': not a JSON object");

  // the pictures
  PlotInputs in = read_plot_inputs(dir);
  const std::string launch = string_or(metrics, "launch", "");
  const std::string launch_name = launch.empty() ? "mission" : fs::path(launch).filename().string();
  PlotOptions top{.title = "Top view: " + launch_name};
  if (auto r = write_top_view_png(in.mesh, in.paths, (dir / "top_view.png").string(), top); !r)
    return r;
  PlotOptions cov{.title = "Coverage over time: " + launch_name};
  if (auto r = write_coverage_png(in.coverage, (dir / "coverage.png").string(), cov); !r) return r;
  std::map<uint32_t, uint64_t> last_ises;  // robot -> ISEs left of its latest sample
  std::map<uint32_t, double> last_t;
  for (const CoverageSample& s : in.coverage)
    if (!last_t.contains(s.robot_id) || s.t_s >= last_t[s.robot_id]) {
      last_t[s.robot_id] = s.t_s;
      last_ises[s.robot_id] = s.ises_left;
    }

  SceneSections scene = scene_sections(run_dir, in.paths, scene_robots(metrics));
  in.notes.insert(in.notes.end(), scene.notes.begin(), scene.notes.end());

  // the page
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>"
       << "Mission report: " << markup_escape(launch_name) << "</title>\n<style>" << kCss
       << "</style>\n</head>\n<body>\n<h1>Mission report: " << markup_escape(launch_name)
       << "</h1>\n<p class=\"sub\">" << (launch.empty() ? kMissing : markup_escape(launch))
       << " &middot; started " << cell(metrics, "started", Format::kText) << " &middot; "
       << cell(metrics, "architecture", Format::kText) << "</p>\n";
  if (metrics.contains("command"))
    html << "<p class=\"sub\">Command: <code>" << cell(metrics, "command", Format::kText)
         << "</code></p>\n";
  for (const std::string& note : in.notes)
    html << "<p class=\"note\">Left out of the pictures: " << markup_escape(note) << "</p>\n";
  summary_table(html, metrics);
  html << "<h2>Top view</h2>\n<figure><img src=\"top_view.png\" alt=\"top view of the "
          "reconstruction and the robots' paths\">\n<figcaption>The reconstruction seen from "
          "above, grey by height (darker is higher), and each robot's path from its start "
          "(circle) to its end (square). White inside the mesh, as on the tops of boxes: "
          "surface no camera saw, above the robots' cameras (unobservable from their height), "
          "not a hole in the reconstruction.</figcaption></figure>\n";
  html << scene.view_html;
  html << "<h2>Coverage</h2>\n<figure><img src=\"coverage.png\" alt=\"coverage over time\">\n"
          "<figcaption>Each robot's coverage of the scene's surface over time, with the 90 % "
          "and 95 % levels, and the ISEs (incomplete surface elements, thesis Definition 1) left "
          "in its map. Robots whose curves coincide (in a distributed run each ends with the "
          "team's map) are drawn with different dashes so that each shows."
          "</figcaption></figure>\n";
  robot_table(html, metrics, last_ises);
  html << scene.contribution_html;
  time_bars(html, metrics);
  compute_table(html, metrics);
  file_table(html, dir);
  html << "</body>\n</html>\n";

  const fs::path out_path = dir / "report.html";
  std::ofstream out(out_path, std::ios::binary | std::ios::trunc);
  out << html.str();
  out.close();
  if (!out) return make_unexpected("cannot write '" + out_path.string() + "'");
  return {};
}

}  // namespace scancrew::report
