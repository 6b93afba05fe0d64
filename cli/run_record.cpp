#include "cli/run_record.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <utility>

#include "cli/build_info.hpp"
#include "cli/mission_compose.hpp"
#include "executors/log.hpp"
#include "executors/params_impl.hpp"
#include "executors/registry.hpp"

namespace scancrew::cli {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::vector<std::string>& stored_command_line() {
  static std::vector<std::string> words;
  return words;
}

bool is_shell_safe(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
         std::string_view("_@%+=:,./-").find(c) != std::string_view::npos;
}

constexpr const char* kResolvedHeader =
    "# The launch file of this run as it was composed (a mission file's composed graph), with\n"
    "# the run's --set overrides applied (run.json lists them and the command), and every\n"
    "# component parameter the launch file left out written with the default it took.\n"
    "# `scancrew rerun <this run directory>` runs it again; {out} stands for the run directory.\n";

// Every `seed` or `*_seed` parameter the resolved launch file sets: "component.key" -> value.
Json seeds_of(const YAML::Node& root) {
  Json seeds = Json::object();
  const YAML::Node components = root["components"];
  if (!components.IsSequence()) return seeds;
  for (const YAML::Node& c : components) {
    if (!c.IsMap() || !c["params"].IsMap()) continue;
    const YAML::Node named = c["name"].IsDefined() ? c["name"] : c["type"];
    const std::string name = named.IsScalar() ? named.Scalar() : "?";
    for (const auto& kv : c["params"]) {
      const std::string key = kv.first.Scalar();
      if (key != "seed" && !key.ends_with("_seed")) continue;
      long long n = 0;
      seeds[name + "." + key] = YAML::convert<long long>::decode(kv.second, n)
                                    ? Json(n)
                                    : Json(kv.second.IsScalar() ? kv.second.Scalar() : "?");
    }
  }
  return seeds;
}

// Whether `override` (--set name.key=value) sets component `name`'s parameter `key`.
bool sets_param(const std::string& override, const std::string& name, const std::string& key) {
  return override.starts_with(name + "." + key + "=");
}

// The relative paths of the files the run read, made absolute, so that the resolved file,
// read from the run directory, names the same files. A component reads a relative input path
// (Component::input_path) beside its launch file (`launch_dir`), or, given with --set, in the
// working directory; a parameter is taken for such a path when it names a file or folder
// that exists there. "{out}" paths (the run's outputs) and other values are left as they are.
void absolute_input_paths(YAML::Node& root, const fs::path& launch_dir,
                          const std::vector<std::string>& overrides) {
  YAML::Node components = root["components"];
  if (!components.IsSequence()) return;
  for (YAML::Node c : components) {
    if (!c.IsMap() || !c["params"].IsMap()) continue;
    const YAML::Node named = c["name"].IsDefined() ? c["name"] : c["type"];
    const std::string name = named.IsScalar() ? named.Scalar() : "";
    for (auto kv : c["params"]) {
      if (!kv.second.IsScalar()) continue;
      const std::string value = kv.second.Scalar(), key = kv.first.Scalar();
      if (value.empty() || value.find('{') != std::string::npos || fs::path(value).is_absolute())
        continue;
      bool set = false;
      for (const std::string& o : overrides) set = set || sets_param(o, name, key);
      std::error_code ec;
      const fs::path base = set ? fs::current_path(ec) : launch_dir;
      if (!ec && fs::exists(base / value, ec))
        kv.second = fs::absolute(base / value, ec).lexically_normal().string();
    }
  }
}

// Writes each component parameter the launch file leaves out with the value its component
// took (ComponentRegistry::effective_parameters), so the file lists every parameter.
void add_defaulted_params(YAML::Node& root) {
  YAML::Node components = root["components"];
  if (!components.IsSequence()) return;
  const auto& registry = ComponentRegistry::instance();
  for (YAML::Node c : components) {
    if (!c.IsMap() || !c["type"].IsScalar()) continue;
    if (c["params"].IsDefined() && !c["params"].IsMap()) continue;
    const YAML::Node given = c["params"].IsDefined() ? c["params"] : YAML::Node();
    YAML::Node params = given.IsDefined() ? given : YAML::Node(YAML::NodeType::Map);
    bool added = false;
    for (const ParamInfo& p : registry.effective_parameters(c["type"].Scalar(), given)) {
      if (std::as_const(params)[p.key].IsDefined()) continue;  // (const: no zombie key)
      try {
        params[p.key] = YAML::Load(p.default_value);
        added = true;
      } catch (const YAML::Exception&) {
        continue;  // (cannot happen: effective() writes YAML; leave the key to its default)
      }
    }
    if (added && !given.IsDefined()) c["params"] = params;
  }
}

bool write_text(const fs::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file << text;
  file.close();
  if (file) return true;
  std::fprintf(stderr, "scancrew run: cannot write %s\n", path.c_str());
  return false;
}

// run.json's description of the binary: version, commit, libraries.
void add_build(Json& j) {
  j["scancrew_version"] = scancrew_version();
  j["git_commit"] = git_commit();
  Json dependencies = Json::object();
  for (const Dependency& d : dependency_versions()) dependencies[d.name] = d.version;
  j["dependencies"] = std::move(dependencies);
}

}  // namespace

void set_command_line(int argc, const char* const* argv) {
  stored_command_line().assign(argv, argv + argc);
}

const std::vector<std::string>& command_line() {
  return stored_command_line();
}

std::string shell_quoted(const std::vector<std::string>& words) {
  std::string line;
  for (const std::string& w : words) {
    if (!line.empty()) line += ' ';
    bool safe = !w.empty();
    for (const char c : w) safe = safe && is_shell_safe(c);
    if (safe) {
      line += w;
      continue;
    }
    line += '\'';
    for (const char c : w) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

Result<std::string, std::string> resolved_launch_text(const std::string& path, size_t robots,
                                                      const std::vector<std::string>& overrides) {
  const auto text = launch_file_text(path, robots);
  if (!text) return make_unexpected(text.error());
  auto root = parse_yaml(*text, path);
  if (!root) return make_unexpected(root.error());
  if (const auto errors = apply_launch_overrides(*root, overrides, path); !errors.empty())
    return make_unexpected(path + ": " + errors.front());
  add_defaulted_params(*root);
  absolute_input_paths(*root, fs::path(path).parent_path(), overrides);
  YAML::Emitter out;
  out << *root;
  if (!out.good())
    return make_unexpected(path + ": cannot write it as YAML: " + out.GetLastError());
  return std::string(kResolvedHeader) + out.c_str() + "\n";
}

bool write_run_record(const fs::path& out, const RunOptions& o) {
  const auto resolved = resolved_launch_text(o.launch_path, o.robot_count, o.sets);
  if (!resolved) {
    std::fprintf(stderr, "scancrew run: %s\n", scancrew::log::printable(resolved.error()).c_str());
    return false;
  }
  Json j;
  j["command"] = shell_quoted(command_line());
  j["argv"] = command_line();
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  j["cwd"] = ec ? Json(nullptr) : Json(cwd.string());
  j["launch"] = o.launch_path;
  j["resolved_launch"] = kResolvedLaunchFile;
  j["sets"] = o.sets;
  j["robots"] = o.robot_count;
  j["trace_events"] = o.trace_events;
  j["process"] = o.process;
  j["out"] = out.string();
  if (!o.rerun_of.empty()) j["rerun_of"] = o.rerun_of;
  const auto root = parse_yaml(*resolved, kResolvedLaunchFile);
  j["seeds"] = root ? seeds_of(*root) : Json::object();
  add_build(j);
  return write_text(out / kResolvedLaunchFile, *resolved) &&
         write_text(out / kRunRecordFile, j.dump(2) + "\n");
}

}  // namespace scancrew::cli
