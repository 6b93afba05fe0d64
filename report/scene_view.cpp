#include "report/scene_view.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>
#include <span>
#include <unordered_map>

#include "core/tsdf/ply_mesh.hpp"
#include "report/plots.hpp"

namespace scancrew::report {
namespace {

using Json = nlohmann::json;
using Vec3f = std::array<float, 3>;

std::string colour_hex(uint32_t robot_id) {
  const auto rgb = robot_colour_rgb(robot_id);
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return buf;
}

std::string base64(std::span<const uint8_t> bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t b0 = bytes[i], b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0,
                   b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const uint32_t v = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

template <class T>
std::string base64_of(const std::vector<T>& values) {
  return base64({reinterpret_cast<const uint8_t*>(values.data()), values.size() * sizeof(T)});
}

// Per vertex, the robot whose owner colour it has (0: none); empty when no vertex has one.
std::vector<uint8_t> vertex_owners(const ColouredPly& mesh, const std::vector<SceneRobot>& robots) {
  if (mesh.colours.size() != mesh.positions.size()) return {};
  std::vector<uint8_t> owners(mesh.positions.size(), 0);
  bool any = false;
  for (const SceneRobot& r : robots) {
    if (r.id == 0 || r.id > 255) continue;
    const auto colour = tsdf::owner_colour(r.id);
    for (size_t i = 0; i < owners.size(); ++i)
      if (mesh.colours[i] == colour) owners[i] = static_cast<uint8_t>(r.id), any = true;
  }
  return any ? owners : std::vector<uint8_t>{};
}

double triangle_area(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2],
               z = u[0] * v[1] - u[1] * v[0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

// The mesh as the view draws it: positions, owners per vertex (or none), triangles.
struct ViewMesh {
  std::vector<Vec3f> positions;
  std::vector<uint8_t> owners;
  std::vector<std::array<uint32_t, 3>> triangles;
};

// Vertex clustering (Rossignac & Borrel 1993): vertices in the same cell of cell_m merge
// into their mean (keeping the first one's owner); triangles that lose a corner are dropped.
ViewMesh cluster(const ColouredPly& m, const std::vector<uint8_t>& owners, double cell_m) {
  ViewMesh out;
  std::unordered_map<uint64_t, uint32_t> cell_of;
  std::vector<uint32_t> remap(m.positions.size());
  std::vector<std::array<double, 4>> sums;  // x, y, z, count
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const auto& p = m.positions[i];
    uint64_t key = 0;
    for (int k = 0; k < 3; ++k)
      key = key * 2097152u + static_cast<uint64_t>(std::floor(p[k] / cell_m) + 1048576) % 2097152u;
    const auto [it, fresh] = cell_of.try_emplace(key, static_cast<uint32_t>(sums.size()));
    if (fresh) {
      sums.push_back({0, 0, 0, 0});
      out.owners.push_back(owners.empty() ? 0 : owners[i]);
    }
    remap[i] = it->second;
    auto& s = sums[it->second];
    s = {s[0] + p[0], s[1] + p[1], s[2] + p[2], s[3] + 1};
  }
  for (const auto& s : sums)
    out.positions.push_back({static_cast<float>(s[0] / s[3]), static_cast<float>(s[1] / s[3]),
                             static_cast<float>(s[2] / s[3])});
  for (const auto& t : m.triangles) {
    const std::array<uint32_t, 3> r = {remap[t[0]], remap[t[1]], remap[t[2]]};
    if (r[0] != r[1] && r[1] != r[2] && r[0] != r[2]) out.triangles.push_back(r);
  }
  if (owners.empty()) out.owners.clear();
  return out;
}

// The mesh within max_triangles: as it is, or clustered on cells grown until it fits.
ViewMesh view_mesh(const ColouredPly& m, const std::vector<uint8_t>& owners, size_t max_triangles,
                   double* cell_m) {
  *cell_m = 0;
  if (m.triangles.size() <= max_triangles)
    return {.positions = m.positions, .owners = owners, .triangles = m.triangles};
  const double area = mesh_area_m2(m);
  // about two triangles a cell of the surface
  double cell = std::max(1e-3, std::sqrt(2 * area / static_cast<double>(max_triangles)));
  for (int i = 0; i < 40; ++i, cell *= 1.25) {
    ViewMesh v = cluster(m, owners, cell);
    if (v.triangles.size() <= max_triangles) {
      *cell_m = cell;
      return v;
    }
  }
  return {};  // unreachable for a finite mesh: 40 steps grow the cell 7500-fold
}

Json mesh_json(const ColouredPly& m, const std::vector<SceneRobot>& robots,
               const SceneViewConfig& config, SceneJson& out) {
  out.triangles_in_file = m.triangles.size();
  double cell_m = 0;
  const ViewMesh v = view_mesh(m, vertex_owners(m, robots), config.max_triangles, &cell_m);
  out.triangles_shown = v.triangles.size();
  std::array<float, 3> lo{}, hi{};
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = v.positions.empty() ? 0.0f : v.positions[0][k];
  for (const auto& p : v.positions)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  std::vector<uint16_t> q;
  q.reserve(3 * v.positions.size());
  for (const auto& p : v.positions)
    for (int k = 0; k < 3; ++k)
      q.push_back(hi[k] > lo[k] ? static_cast<uint16_t>(
                                      std::lround((p[k] - lo[k]) / (hi[k] - lo[k]) * 65535.0))
                                : 0);
  std::vector<uint32_t> indices;
  indices.reserve(3 * v.triangles.size());
  for (const auto& t : v.triangles) indices.insert(indices.end(), t.begin(), t.end());
  std::string note;
  if (cell_m > 0) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "(decimated for the page: %zu of the file's %zu triangles, %.2f m cells)",
                  v.triangles.size(), m.triangles.size(), cell_m);
    note = buf;
  }
  Json j = {{"triangles", v.triangles.size()},
            {"triangles_in_file", m.triangles.size()},
            {"note", note},
            {"origin", {lo[0], lo[1], lo[2]}},
            {"extent", {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}},
            {"positions", base64_of(q)},
            {"indices", base64_of(indices)}};
  if (!v.owners.empty()) j["owners"] = base64_of(v.owners);
  return j;
}

double round_mm(double x) {
  return std::round(x * 1000) / 1000;
}

Json paths_json(const std::vector<PathSample>& paths, double step_m) {
  std::map<uint32_t, std::vector<const PathSample*>> by_robot;
  for (const PathSample& s : paths) by_robot[s.robot_id].push_back(&s);
  Json out = Json::array();
  for (auto& [id, list] : by_robot) {
    std::stable_sort(list.begin(), list.end(),
                     [](const PathSample* a, const PathSample* b) { return a->t_s < b->t_s; });
    Json points = Json::array();
    const PathSample* kept = nullptr;
    for (size_t i = 0; i < list.size(); ++i) {
      const PathSample& s = *list[i];
      const bool far = kept == nullptr || std::hypot(s.x_m - kept->x_m, s.y_m - kept->y_m,
                                                     s.z_m - kept->z_m) >= step_m;
      if (!far && i + 1 < list.size()) continue;
      for (const double v : {s.x_m, s.y_m, s.z_m}) points.push_back(round_mm(v));
      kept = &s;
    }
    out.push_back({{"robot", id}, {"points", std::move(points)}});
  }
  return out;
}

// The ISE files' points by class (core/ise/ise_ply.cpp's colours), each position once.
Json ises_json(const std::vector<ColouredPly>& files) {
  static constexpr std::array<std::pair<const char*, std::array<uint8_t, 3>>, 3> kClasses = {{
      {"inspectable", {40, 200, 40}},
      {"c_rem", {220, 40, 40}},
      {"viewpoints", {40, 80, 230}},
  }};
  Json out = Json::object();
  for (const auto& [name, colour] : kClasses) {
    std::set<Vec3f> seen;
    Json points = Json::array();
    for (const ColouredPly& f : files)
      for (size_t i = 0; i < f.positions.size() && i < f.colours.size(); ++i)
        if (f.colours[i] == colour && seen.insert(f.positions[i]).second)
          for (const float v : f.positions[i]) points.push_back(round_mm(v));
    out[name] = std::move(points);
  }
  return out;
}

}  // namespace

std::map<uint32_t, double> surface_by_robot_m2(const ColouredPly& mesh,
                                               const std::vector<SceneRobot>& robots) {
  const std::vector<uint8_t> owners = vertex_owners(mesh, robots);
  std::map<uint32_t, double> area;
  if (owners.empty()) return area;
  for (const SceneRobot& r : robots) area[r.id] = 0;
  for (const auto& t : mesh.triangles)
    if (owners[t[0]] != 0)
      area[owners[t[0]]] +=
          triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  return area;
}

double mesh_area_m2(const ColouredPly& mesh) {
  double area = 0;
  for (const auto& t : mesh.triangles)
    area += triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  return area;
}

SceneJson scene_json(const ColouredPly& mesh, const std::vector<PathSample>& paths,
                     const std::vector<SceneRobot>& robots,
                     const std::vector<ColouredPly>& ise_files, const SceneViewConfig& config) {
  SceneJson out;
  Json robots_json = Json::array();
  std::set<uint32_t> ids;
  for (const SceneRobot& r : robots) ids.insert(r.id);
  for (const PathSample& s : paths) ids.insert(s.robot_id);
  for (const uint32_t id : ids) {
    std::string name = "r" + std::to_string(id);
    for (const SceneRobot& r : robots)
      if (r.id == id && !r.name.empty()) name = r.name;
    robots_json.push_back({{"id", id}, {"name", name}, {"colour", colour_hex(id)}});
  }
  Json j = {{"robots", std::move(robots_json)},
            {"mesh", mesh_json(mesh, robots, config, out)},
            {"paths", paths_json(paths, config.path_step_m)},
            {"ises", ises_json(ise_files)},
            {"point_size_m", config.point_size_m}};
  std::string text = j.dump(-1, ' ', false, Json::error_handler_t::replace);
  // inside <script>: "</" could close it; "<\/" is the same JSON string
  for (size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  out.json = std::move(text);
  return out;
}

}  // namespace scancrew::report
