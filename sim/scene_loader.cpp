// Scene files (launch_cfg/scenes/*.yaml) -> SceneSpec, with every error named.

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "executors/params_impl.hpp"
#include "sim/mesh_io.hpp"
#include "sim/scene.hpp"

namespace scancrew::sim {

namespace {

class SceneReader {
 public:
  SceneReader(std::string label, std::string base_dir)
      : label_(std::move(label)), base_dir_(std::move(base_dir)) {}

  Result<SceneSpec, std::vector<std::string>> read(const YAML::Node& root) {
    SceneSpec s;
    s.source = label_;
    if (!root.IsMap())
      return fail(label_ + ": a scene file is a mapping (name, bounds, boxes, ...)");
    ParamReader top = make_param_reader(root, label_, "scene");
    top.required("name", s.name);
    std::vector<double> min, max;
    top.optional_list("bounds_min_m", min, 3);
    top.optional_list("bounds_max_m", max, 3);
    top.optional("ceiling", s.ceiling);
    top.optional("wall_height_m", s.wall_height_m, {0, 100});
    top.optional("wall_thickness_m", s.wall_thickness_m, {0.01, 10});
    top.choice("walls_texture", s.walls_texture, kSurfaceTextureNames);
    top.optional("dot_size_m", s.dot_size_m, {0.001, 1});
    top.optional("texture_seed", s.texture_seed);
    for (const char* list : {"boxes", "cylinders", "meshes", "starts"}) top.mark_known(list);
    top.finish();
    merge(top);
    if (min.size() != 3 || max.size() != 3) {
      errors_.push_back(
          yaml_location(label_, root) +
          ": scene.bounds_min_m / bounds_max_m: required; allowed: [x, y, z] each, min < max");
    } else {
      s.min_m = {min[0], min[1], min[2]};
      s.max_m = {max[0], max[1], max[2]};
      if (!(s.min_m.x < s.max_m.x && s.min_m.y < s.max_m.y && s.min_m.z < s.max_m.z))
        errors_.push_back(yaml_location(label_, root["bounds_min_m"]) +
                          ": scene.bounds: degenerate, min must be < max on every axis");
    }
    read_list(root["boxes"], "boxes",
              [&](ParamReader& r, const std::string& path) { read_box(r, path, s); });
    read_list(root["cylinders"], "cylinders",
              [&](ParamReader& r, const std::string& path) { read_cylinder(r, path, s); });
    read_list(root["meshes"], "meshes",
              [&](ParamReader& r, const std::string& path) { read_mesh(r, path, s); });
    read_starts(root["starts"], s);
    check_names(s);
    if (!errors_.empty()) return make_unexpected(errors_);
    return s;
  }

  Result<SceneSpec, std::vector<std::string>> fail(std::string message) {
    errors_.push_back(std::move(message));
    return make_unexpected(errors_);
  }

 private:
  // object names become MuJoCo names: unique, and not those the builder uses itself
  void check_names(const SceneSpec& s) {
    std::set<std::string> seen = {"floor",      "ceiling",   "wall_north",
                                  "wall_south", "wall_east", "wall_west"};
    const auto check = [&](const std::string& kind, const std::string& name) {
      if (name.empty()) return;
      if (!seen.insert(name).second)
        errors_.push_back(label_ + ": " + kind + " '" + name +
                          "': the name is used twice or is reserved "
                          "(floor, ceiling, wall_north/south/east/west)");
    };
    for (const auto& b : s.boxes) check("box", b.name);
    for (const auto& c : s.cylinders) check("cylinder", c.name);
    for (const auto& m : s.meshes) check("mesh", m.name);
  }

  void merge(const ParamReader& r) {
    errors_.insert(errors_.end(), r.errors().begin(), r.errors().end());
  }

  template <class Fn>
  void read_list(const YAML::Node& node, const std::string& key, Fn&& fn) {
    if (!node.IsDefined() || node.IsNull()) return;
    if (!node.IsSequence()) {
      errors_.push_back(yaml_location(label_, node) + ": scene." + key + ": must be a list");
      return;
    }
    for (size_t i = 0; i < node.size(); ++i) {
      const std::string path = key + "[" + std::to_string(i) + "]";
      ParamReader r = make_param_reader(node[i], label_, path);
      fn(r, path);
      r.finish();
      merge(r);
    }
  }

  bool vec3(ParamReader& r, const char* key, msg::Vec3& out, bool positive) {
    std::vector<double> v;
    r.optional_list(key, v, 3, positive ? Range{1e-3, 1e4} : Range{-1e4, 1e4});
    if (v.size() != 3) {
      if (r.ok())
        r.report(key, std::string("required; allowed: [x, y, z]") +
                          (positive ? ", each > 0.001 m" : ""));
      return false;
    }
    out = {v[0], v[1], v[2]};
    return true;
  }

  void color(ParamReader& r, Rgb& c) {
    std::vector<double> v;
    r.optional_list("color", v, 3, {0, 1});
    if (v.size() == 3) c = {v[0], v[1], v[2]};
  }

  void read_box(ParamReader& r, const std::string& /*path*/, SceneSpec& s) {
    BoxSpec b;
    r.required("name", b.name);
    vec3(r, "center_m", b.center_m, false);
    vec3(r, "size_m", b.size_m, true);
    double yaw_deg = 0;
    r.optional("yaw_deg", yaw_deg, {-360, 360});
    b.yaw_rad = yaw_deg * M_PI / 180.0;
    color(r, b.color);
    r.choice("texture", b.texture, kSurfaceTextureNames);
    s.boxes.push_back(b);
  }

  void read_cylinder(ParamReader& r, const std::string& /*path*/, SceneSpec& s) {
    CylinderSpec c;
    r.required("name", c.name);
    vec3(r, "center_m", c.center_m, false);
    r.required("radius_m", c.radius_m, {1e-3, 1e4});
    r.required("height_m", c.height_m, {1e-3, 1e4});
    color(r, c.color);
    r.choice("texture", c.texture, kSurfaceTextureNames);
    s.cylinders.push_back(c);
  }

  void read_mesh(ParamReader& r, const std::string& /*path*/, SceneSpec& s) {
    MeshSpec m;
    r.required("name", m.name);
    r.required("file", m.file);
    vec3(r, "fit_m", m.fit_m, true);
    vec3(r, "center_m", m.center_m, false);
    r.optional("attribution", m.attribution);
    color(r, m.color);
    if (!m.file.empty()) {
      std::filesystem::path p(m.file);
      if (p.is_relative()) p = std::filesystem::path(base_dir_) / p;
      m.file = p.lexically_normal().string();
      if (!mesh_format_supported(p.extension().string()))
        r.report("file", "'" + m.file +
                             "': not a mesh format assimp reads (use COLLADA, OBJ, STL, PLY, ...)");
      else if (!std::filesystem::exists(p))
        r.report("file", "mesh file '" + m.file + "' does not exist");
    }
    s.meshes.push_back(m);
  }

  // starts: {ground: [[x, y, z, yaw_deg], ...], multirotor: [...]}, each inside the bounds
  void read_starts(const YAML::Node& node, SceneSpec& s) {
    if (!node.IsDefined() || node.IsNull()) return;
    if (!node.IsMap()) {
      errors_.push_back(yaml_location(label_, node) +
                        ": scene.starts: must be a mapping {ground: [...], multirotor: [...]}");
      return;
    }
    ParamReader keys = make_param_reader(node, label_, "starts");
    for (const char* kind : {"ground", "multirotor"}) keys.mark_known(kind);
    keys.finish();
    merge(keys);
    read_start_list(node["ground"], "ground", s, s.starts.ground);
    read_start_list(node["multirotor"], "multirotor", s, s.starts.multirotor);
  }

  void read_start_list(const YAML::Node& node, const std::string& kind, const SceneSpec& s,
                       std::vector<StartPose>& out) {
    if (!node.IsDefined() || node.IsNull()) return;
    const std::string key = "scene.starts." + kind;
    if (!node.IsSequence()) {
      errors_.push_back(yaml_location(label_, node) + ": " + key +
                        ": must be a list of [x, y, z, yaw_deg]");
      return;
    }
    for (size_t i = 0; i < node.size(); ++i) {
      const YAML::Node& item = node[i];
      const std::string where =
          yaml_location(label_, item) + ": " + key + "[" + std::to_string(i) + "]";
      double v[4] = {};
      bool ok = item.IsSequence() && item.size() == 4;
      for (size_t k = 0; ok && k < 4; ++k) {
        try {
          v[k] = item[k].as<double>();
        } catch (const YAML::Exception&) {
          ok = false;
        }
      }
      if (!ok) {
        errors_.push_back(where + ": allowed: [x, y, z, yaw_deg], four numbers");
        continue;
      }
      const msg::Vec3 p{v[0], v[1], v[2]};
      if (p.x < s.min_m.x || p.x > s.max_m.x || p.y < s.min_m.y || p.y > s.max_m.y ||
          p.z < s.min_m.z || p.z > s.max_m.z) {
        errors_.push_back(where +
                          ": outside the bounds; allowed: a point inside bounds_min_m / "
                          "bounds_max_m");
        continue;
      }
      if (v[3] < -360 || v[3] > 360) {
        std::ostringstream yaw;
        yaw << v[3];
        errors_.push_back(where + ": yaw_deg " + yaw.str() +
                          " is out of range; allowed: [-360, 360]");
        continue;
      }
      out.push_back({p, v[3] * M_PI / 180.0});
    }
  }

  std::string label_, base_dir_;
  std::vector<std::string> errors_;
};

}  // namespace

Result<SceneSpec, std::vector<std::string>> parse_scene(const std::string& yaml_text,
                                                        const std::string& label,
                                                        const std::string& base_dir) {
  SceneReader reader(label, base_dir);
  auto root = parse_yaml(yaml_text, label);
  if (!root) return reader.fail(root.error());
  return reader.read(*root);
}

Result<SceneSpec, std::vector<std::string>> load_scene(const std::string& path) {
  const auto text = read_text_file(path);
  if (!text)
    return make_unexpected(
        std::vector<std::string>{path + ": cannot read the scene file: " + text.error()});
  return parse_scene(*text, path, std::filesystem::path(path).parent_path().string());
}

}  // namespace scancrew::sim
