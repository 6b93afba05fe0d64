#pragma once

// The report's 3D view (docs/visualization.md, "The report's 3D view") and what each robot
// contributed. The view is a three.js page script (web/report_viewer/main.js, bundled at build
// time: report/viewer_script.hpp) inlined into report.html with the scene as JSON, so the
// page opens offline from file://.
//
// The scene JSON (<script type="application/json" id="scancrew-scene">):
//   robots   [{id, name, colour "#rrggbb"}]              the report's robot colours
//   mesh     {triangles, triangles_in_file, note, origin [x,y,z], extent [x,y,z],
//             positions: base64 uint16 x,y,z per vertex, quantised over origin + extent,
//             indices: base64 uint32 per triangle corner,
//             owners: base64 uint8 robot id per vertex (0: none), absent without owners}
//   paths    [{robot, points [x,y,z, ...]}]               a point every path_step_m
//   ises     {viewpoints, inspectable, c_rem: [x,y,z, ...]}  from the ises*.ply files
//   point_size_m
// Little-endian arrays (every browser's typed arrays on x86-64 and ARM).
//
// Owners: tsdf_mapper colours its mesh by the robot whose patches carry most of each block's
// weight (core/tsdf/ply_mesh.hpp, owner_colour); a vertex of robot r's owner colour is
// robot r's. Single-robot and centralized maps colour nothing by robot: no owners.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "report/coloured_ply.hpp"
#include "report/run_files.hpp"

namespace scancrew::report {

struct SceneRobot {
  uint32_t id = 0;
  std::string name;                    // its namespace, e.g. "r1"
  std::optional<uint64_t> bytes_sent;  // map patches it sent (metrics.json), if known
};

struct SceneViewConfig {
  // above this, the mesh is decimated by vertex clustering and the page says so; keeps the
  // page to a few MB (positions 6 B a vertex, indices 12 B a triangle, base64 4/3)
  size_t max_triangles = 200000;
  double path_step_m = 0.05;  // a path keeps a point every this far (and its last)
  double point_size_m = 0.2;  // drawn size of ISE and viewpoint points
};

// Per robot id: the area (m²) of the mesh's triangles whose first vertex has that robot's
// owner colour. Empty when the mesh has no vertex of any robot's owner colour.
std::map<uint32_t, double> surface_by_robot_m2(const ColouredPly& mesh,
                                               const std::vector<SceneRobot>& robots);

// The area (m²) of all the mesh's triangles.
double mesh_area_m2(const ColouredPly& mesh);

struct SceneJson {
  std::string json;  // HTML-safe: "</" written "<\/"
  size_t triangles_in_file = 0, triangles_shown = 0;
};

// ise_files: the run directory's ises*.ply point sets (points of the same class and
// position in several files are shown once).
SceneJson scene_json(const ColouredPly& mesh, const std::vector<PathSample>& paths,
                     const std::vector<SceneRobot>& robots,
                     const std::vector<ColouredPly>& ise_files, const SceneViewConfig& config = {});

// The report's "3D view" section: the view's container, its legend, the scene and the script.
std::string scene_view_html(const SceneJson& scene);

// The report's "What each robot contributed" section: per robot the surface its patches made
// (surface_by_robot_m2, with its share of the mesh) and the map data it sent.
std::string contribution_html(const std::vector<SceneRobot>& robots,
                              const std::map<uint32_t, double>& surface_m2, double total_area_m2);

// Both sections of a run directory: its mesh.ply and ises*.ply read here (a file that
// cannot be read adds a note and is left out), paths from paths.csv.
struct SceneSections {
  std::string view_html, contribution_html;
  std::vector<std::string> notes;
};
SceneSections scene_sections(const std::string& run_dir, const std::vector<PathSample>& paths,
                             const std::vector<SceneRobot>& robots);

}  // namespace scancrew::report
