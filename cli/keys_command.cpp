#include "cli/keys_command.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/mission_compose.hpp"
#include "components/dds_bridge/dds_bridge.hpp"
#include "components/dds_bridge/dds_link.hpp"
#include "executors/log.hpp"
#include "executors/params_impl.hpp"

namespace scancrew::cli {
namespace {

// A string list of a bridge's params (absent: empty).
Result<std::vector<std::string>, std::string> string_list(const YAML::Node& params,
                                                          const char* key) {
  std::vector<std::string> out;
  const YAML::Node node = params[key];
  if (!node.IsDefined() || node.IsNull()) return out;
  if (!node.IsSequence()) return make_unexpected(std::string(key) + ": must be a list");
  for (const YAML::Node& item : node) {
    if (!item.IsScalar()) return make_unexpected(std::string(key) + ": must list names");
    out.push_back(item.Scalar());
  }
  return out;
}

template <class T>
Result<T, std::string> scalar(const YAML::Node& params, const char* key, T fallback) {
  const YAML::Node node = params[key];
  if (!node.IsDefined() || node.IsNull()) return fallback;
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    return make_unexpected(std::string(key) + ": not a valid value");
  }
}

void add_unique(std::vector<std::string>& list, const std::string& name) {
  if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
}

std::string place_of(const KeysOptions& o) {
  if (o.station) return "station";
  if (o.sim) return "sim";
  return "robot_" + std::to_string(o.robot);
}

}  // namespace

Result<dds_bridge::PlaceGrant, std::string> grant_from_launch(
    const std::string& launch_text, const std::string& label, const std::string& place,
    const std::vector<std::string>& overrides) {
  auto root = parse_yaml(launch_text, label);
  if (!root) return make_unexpected(root.error());
  // the bridges' topics as the launch runs them (`--set dds_bridge.export_topics=...`)
  if (const auto errors = apply_launch_overrides(*root, overrides, label); !errors.empty())
    return make_unexpected(errors.front());
  std::vector<TeamMember> team;
  if (const YAML::Node robots = (*root)["robots"]; robots.IsSequence())
    for (const YAML::Node& r : robots) {
      TeamMember m;
      auto id = scalar<uint32_t>(r, "id", 0);
      auto ns = scalar<std::string>(r, "namespace", "");
      if (!id || !ns)
        return make_unexpected(label + ": robots: " + (!id ? id.error() : ns.error()));
      m.id = *id;
      m.ns = *ns;
      team.push_back(m);
    }
  dds_bridge::PlaceGrant grant;
  grant.place = place;
  size_t bridges = 0;
  if (const YAML::Node components = (*root)["components"]; components.IsSequence())
    for (const YAML::Node& c : components) {
      if (!c.IsMap() || !c["type"].IsScalar() || c["type"].Scalar() != "dds_bridge") continue;
      // no name: named by its type
      const std::string name =
          c["name"].IsDefined() && c["name"].IsScalar() ? c["name"].Scalar() : "dds_bridge";
      auto fail = [&](const std::string& e) {
        return make_unexpected(label + ": component '" + name + "': " + e);
      };
      const YAML::Node params = c["params"];
      auto per_robot = scalar<bool>(c, "per_robot", true);
      auto bridge_id = scalar<int64_t>(params, "bridge_id", -1);
      auto simulator_id = scalar<uint32_t>(params, "simulator_id", 65535);
      auto prefix = scalar<std::string>(params, "dds_prefix", "sc/");
      auto exports = string_list(params, "export_topics");
      auto imports = string_list(params, "import_topics");
      for (const std::string* e :
           {per_robot ? nullptr : &per_robot.error(), bridge_id ? nullptr : &bridge_id.error(),
            simulator_id ? nullptr : &simulator_id.error(), prefix ? nullptr : &prefix.error(),
            exports ? nullptr : &exports.error(), imports ? nullptr : &imports.error()})
        if (e != nullptr) return fail(*e);
      std::vector<uint32_t> owners;
      if (*per_robot)
        for (const TeamMember& m : team) owners.push_back(m.id);
      else
        owners.push_back(0);
      for (const uint32_t owner : owners) {
        const auto self = *bridge_id >= 0 ? static_cast<uint32_t>(*bridge_id) : owner;
        if (dds_bridge::place_name(self, *simulator_id) != place) continue;
        ++bridges;
        for (const auto& [names, out] :
             {std::pair{&*exports, &grant.publish}, std::pair{&*imports, &grant.subscribe}})
          for (const std::string& n : *names) {
            auto expanded = dds_bridge::expand_topic_name(n, team, owner);
            if (!expanded) return fail(expanded.error());
            for (const std::string& e : *expanded)
              add_unique(*out, dds_bridge::dds_topic_name(*prefix, e));
          }
      }
    }
  if (bridges == 0)
    return make_unexpected(label + ": no dds_bridge component runs as '" + place +
                           "' (robot bridges are per robot; the station's has bridge_id 0, the "
                           "simulator's its simulator_id)");
  // every bridge announces itself and, split over processes, steps in lockstep
  for (std::vector<std::string>* list : {&grant.publish, &grant.subscribe}) {
    add_unique(*list, std::string(dds_bridge::kPresenceTopic));
    add_unique(*list, std::string(dds_bridge::kLockstepTopic));
  }
  return grant;
}

int run_keys_init(const KeysOptions& o) {
  if (auto made = dds_bridge::init_team_keys(o.dir, o.team); !made) {
    std::fprintf(stderr, "scancrew keys init: %s\n", log::printable(made.error()).c_str());
    return 1;
  }
  std::printf("keys: team '%s': authority %s/ca.pem, governance %s/governance.p7s\n",
              o.team.c_str(), o.dir.c_str(), o.dir.c_str());
  std::printf("keys: keep %s/ca.key off the robots; add each place with `scancrew keys add`\n",
              o.dir.c_str());
  return 0;
}

int run_keys_add(const KeysOptions& o) {
  const int chosen = (o.robot >= 0 ? 1 : 0) + (o.station ? 1 : 0) + (o.sim ? 1 : 0);
  if (chosen != 1) {
    std::fprintf(stderr, "scancrew keys add: name one place: --robot K, --station or --sim\n");
    return 1;
  }
  const std::string place = place_of(o);
  auto text = launch_file_text(o.launch);
  if (!text) {
    std::fprintf(stderr, "scancrew keys add: %s\n", log::printable(text.error()).c_str());
    return 1;
  }
  auto grant = grant_from_launch(*text, o.launch, place, o.overrides);
  if (!grant) {
    std::fprintf(stderr, "scancrew keys add: %s\n", log::printable(grant.error()).c_str());
    return 1;
  }
  if (auto added = dds_bridge::add_place_keys(o.dir, *grant); !added) {
    std::fprintf(stderr, "scancrew keys add: %s\n", log::printable(added.error()).c_str());
    return 1;
  }
  std::printf("keys: %s: %s/%s.pem, %s.key, permissions_%s.p7s (publishes %zu topics, reads %zu)\n",
              place.c_str(), o.dir.c_str(), place.c_str(), place.c_str(), place.c_str(),
              grant->publish.size(), grant->subscribe.size());
  return 0;
}

void add_keys_command(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<KeysOptions>();
  auto* keys = app.add_subcommand("keys", "a team's keys for DDS-Security (docs/security.md)");
  keys->require_subcommand(1);
  auto* init = keys->add_subcommand("init", "make a team's authority and governance");
  init->add_option("dir", o->dir, "key folder (made if absent)")->required();
  init->add_option("--team", o->team, "the team's name (default: team)");
  table.add(init, [o] { return run_keys_init(*o); });
  auto* add = keys->add_subcommand(
      "add", "make a place's identity and permissions (from the launch file's bridges)");
  add->add_option("dir", o->dir, "key folder (scancrew keys init)")->required();
  add->add_option("launch", o->launch, "the team's launch file")->required();
  auto* robot = add->add_option("--robot", o->robot, "a robot, by its id")
                    ->check(CLI::Range(int64_t{1}, int64_t{4294967294}));
  auto* station = add->add_flag("--station", o->station, "the ground station");
  auto* sim = add->add_flag("--sim", o->sim, "the simulator");
  robot->excludes(station)->excludes(sim);
  station->excludes(sim);
  add->add_option("--set", o->overrides,
                  "name.key=value: a launch override, as the place runs with it (a "
                  "bridge's topics)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  table.add(add, [o] { return run_keys_add(*o); });
}

}  // namespace scancrew::cli
