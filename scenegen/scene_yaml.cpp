// SceneSpec -> scene file text (docs/sim.md's format), to the millimetre.

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "scenegen/scenegen.hpp"

namespace scancrew::scenegen {

namespace {

// a number to the millimetre, without trailing zeros: 1.5, 2, -0.125
std::string num(double x) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f", x);
  std::string s = text;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

// [a, b, c]
std::string triple(double a, double b, double c) {
  std::string out = "[";
  out.append(num(a)).append(", ").append(num(b)).append(", ").append(num(c)).append("]");
  return out;
}
std::string vec(const msg::Vec3& v) {
  return triple(v.x, v.y, v.z);
}
std::string rgb(const sim::Rgb& c) {
  return triple(c.r, c.g, c.b);
}
std::string deg(double rad) {
  return num(rad * 180.0 / M_PI);
}

// a YAML double-quoted string
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}

void write_starts(std::ostringstream& y, const char* kind, const std::vector<sim::StartPose>& v) {
  if (v.empty()) return;
  y << "  " << kind << ":\n";
  for (const auto& p : v)
    y << "    - [" << num(p.position_m.x) << ", " << num(p.position_m.y) << ", "
      << num(p.position_m.z) << ", " << deg(p.yaw_rad) << "]\n";
}

}  // namespace

std::string write_scene_yaml(const sim::SceneSpec& s, const std::string& header_comment) {
  std::ostringstream y;
  std::istringstream header(header_comment);
  for (std::string line; std::getline(header, line);) y << "# " << line << "\n";
  y << "name: " << s.name << "\n";
  y << "bounds_min_m: " << vec(s.min_m) << "\n";
  y << "bounds_max_m: " << vec(s.max_m) << "\n";
  if (s.wall_height_m > 0) {
    y << "wall_height_m: " << num(s.wall_height_m) << "\n";
    y << "wall_thickness_m: " << num(s.wall_thickness_m) << "\n";
  }
  if (s.ceiling) y << "ceiling: true\n";
  y << "dot_size_m: " << num(s.dot_size_m) << "\n";
  y << "texture_seed: " << s.texture_seed << "\n";
  if (!s.starts.ground.empty() || !s.starts.multirotor.empty()) {
    y << "starts:\n";
    write_starts(y, "ground", s.starts.ground);
    write_starts(y, "multirotor", s.starts.multirotor);
  }
  if (!s.boxes.empty()) y << "boxes:\n";
  for (const auto& b : s.boxes) {
    y << "  - {name: " << b.name << ", center_m: " << vec(b.center_m)
      << ", size_m: " << vec(b.size_m);
    if (num(b.yaw_rad * 180.0 / M_PI) != "0") y << ", yaw_deg: " << deg(b.yaw_rad);
    y << ", color: " << rgb(b.color) << "}\n";
  }
  if (!s.cylinders.empty()) y << "cylinders:\n";
  for (const auto& c : s.cylinders)
    y << "  - {name: " << c.name << ", center_m: " << vec(c.center_m)
      << ", radius_m: " << num(c.radius_m) << ", height_m: " << num(c.height_m)
      << ", color: " << rgb(c.color) << "}\n";
  if (!s.meshes.empty()) y << "meshes:\n";
  for (const auto& m : s.meshes) {
    y << "  - {name: " << m.name << ", file: " << quoted(m.file) << ", fit_m: " << vec(m.fit_m)
      << ", center_m: " << vec(m.center_m) << ", color: " << rgb(m.color);
    if (!m.attribution.empty()) y << ", attribution: " << quoted(m.attribution);
    y << "}\n";
  }
  return y.str();
}

}  // namespace scancrew::scenegen
