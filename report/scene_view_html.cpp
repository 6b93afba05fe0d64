// The HTML of the report's 3D view and of its per-robot contribution table
// (report/scene_view.hpp).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/io/ply.hpp"
#include "core/markup_escape.hpp"
#include "report/plots.hpp"
#include "report/run_files_table.hpp"
#include "report/scene_view.hpp"
#include "report/viewer_script.hpp"

namespace scancrew::report {
namespace {

constexpr const char* kViewCss = R"(
#scancrew-3d{width:100%;border:1px solid #ddd;min-height:200px}
#scancrew-3d canvas{display:block}
#scancrew-3d-legend{display:flex;flex-wrap:wrap;gap:.2em 1.4em;margin:.4em 0}
.v3d-row{white-space:nowrap}.v3d-row input{vertical-align:-.1em}
)";

std::string colour_hex(uint32_t robot_id) {
  const auto rgb = robot_colour_rgb(robot_id);
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return buf;
}

std::string printf_string(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

std::string scene_view_html(const SceneJson& scene) {
  std::ostringstream out;
  out << "<h2>3D view</h2>\n<style>" << kViewCss << "</style>\n"
      << "<div id=\"scancrew-3d\"></div>\n"
      << "<div id=\"scancrew-3d-legend\" class=\"legend\"></div>\n"
      << "<p class=\"legend\"><span class=\"sw\" style=\"background:#f4f5f7;border:1px solid "
         "#bbb\"></span>Background seen through the mesh, e.g. on the tops of boxes: "
         "surface no camera saw. It lies above the robots' cameras (unobservable from their "
         "height), so it is missing from the map, not a hole in the reconstruction; the "
         "evaluation's reachable coverage leaves it out.</p>\n"
      << "<p class=\"small\">Drag to orbit, right-drag (or shift-drag) to pan, wheel to zoom. "
         "<button type=\"button\" id=\"scancrew-3d-reset\">Reset view</button> &middot; mesh: "
      << scene.triangles_shown << " triangles";
  if (scene.triangles_shown != scene.triangles_in_file)
    out << " (decimated from the file's " << scene.triangles_in_file << " for this page)";
  out << ".</p>\n<noscript><p class=\"note\">The 3D view needs JavaScript.</p></noscript>\n"
      << "<script type=\"application/json\" id=\"scancrew-scene\">" << scene.json
      << "</script>\n<script>\n"
      << viewer_script() << "\n</script>\n";
  return out.str();
}

std::string contribution_html(const std::vector<SceneRobot>& robots,
                              const std::map<uint32_t, double>& surface_m2, double total_area_m2) {
  std::ostringstream out;
  out << "<h2>What each robot contributed</h2>\n<table>\n<tr><th>Robot</th>"
         "<th>Surface its patches made (m&sup2;)</th><th>Share of the mesh (%)</th>"
         "<th>Map data it sent</th></tr>\n";
  for (const SceneRobot& r : robots) {
    out << "<tr><td><span class=\"sw\" style=\"background:" << colour_hex(r.id) << "\"></span>"
        << markup_escape(r.name.empty() ? std::to_string(r.id) : r.name) << "</td>";
    const auto s = surface_m2.find(r.id);
    if (s != surface_m2.end())
      out << "<td class=\"n\">" << printf_string("%.1f", s->second) << "</td><td class=\"n\">"
          << (total_area_m2 > 0 ? printf_string("%.1f", 100 * s->second / total_area_m2)
                                : std::string("&mdash;"))
          << "</td>";
    else
      out << "<td>&mdash;</td><td>&mdash;</td>";
    out << "<td class=\"n\">"
        << (r.bytes_sent ? human_bytes(static_cast<double>(*r.bytes_sent)) : std::string("&mdash;"))
        << "</td></tr>\n";
  }
  out << "</table>\n<p class=\"small\">Surface: the area of the mesh in blocks whose weight "
         "comes mostly from the robot's own depth images (the map's block owner, as the mesh's "
         "colours show it and the 3D view tints it); "
      << (surface_m2.empty() ? "&mdash; here: this map does not record owners (one robot, or a "
                               "centralized map that integrates every robot's depth alike). "
                             : "")
      << "data sent: the completed map patches it published (their wire size; distributed "
         "runs only). In a distributed run every robot ends with the team's map, so each "
         "robot's coverage curve is the team's: the coverage plot draws them dashed so that "
         "both show.</p>\n";
  return out.str();
}

SceneSections scene_sections(const std::string& run_dir, const std::vector<PathSample>& paths,
                             const std::vector<SceneRobot>& robots) {
  namespace fs = std::filesystem;
  SceneSections out;
  const fs::path dir(run_dir);
  std::error_code ec;
  ColouredPly mesh;
  // mesh.ply with its owner colours; from another pipeline (an ASCII PLY...), without: a
  // mesh that cannot be read at all is already the top view's note
  if (fs::exists(dir / "mesh.ply", ec)) {
    if (auto m = read_coloured_ply((dir / "mesh.ply").string())) {
      mesh = std::move(m).value();
    } else if (auto plain = io::read_ply_mesh((dir / "mesh.ply").string())) {
      for (const msg::Vec3& v : plain->vertices)
        mesh.positions.push_back(
            {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)});
      mesh.triangles = std::move(plain->triangles);
    }
  }
  // the ISE files: ises.ply (one map) or ises_<robot>.ply, in name order
  std::vector<fs::path> ise_paths;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.starts_with("ises") && name.ends_with(".ply")) ise_paths.push_back(it->path());
  }
  std::sort(ise_paths.begin(), ise_paths.end());
  std::vector<ColouredPly> ises;
  for (const fs::path& p : ise_paths) {
    if (auto f = read_coloured_ply(p.string()))
      ises.push_back(std::move(f).value());
    else
      out.notes.push_back(f.error());
  }
  out.contribution_html =
      contribution_html(robots, surface_by_robot_m2(mesh, robots), mesh_area_m2(mesh));
  out.view_html = scene_view_html(scene_json(mesh, paths, robots, ises));
  return out;
}

}  // namespace scancrew::report
