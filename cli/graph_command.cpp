// `scancrew components`: the registered component types. `scancrew graph <launch.yaml>`: the
// composed graph of a launch file, and its checks.

#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "cli/report.hpp"
#include "cli/run_command.hpp"
#include "executors/registry.hpp"

namespace scancrew::cli {

namespace {

int list_components() {
  const auto& registry = ComponentRegistry::instance();
  for (const auto& type : registry.types())
    std::printf("%-24s %s\n", type.c_str(), registry.find(type)->description.c_str());
  return 0;
}

int print_launch_graph(const std::string& path) {
  auto launch = compose_or_report(path, {});
  if (!launch) return 2;
  print_graph(stdout, *launch);
  return launch->report().errors.empty() ? 0 : 2;
}

}  // namespace

void add_graph_commands(CLI::App& app, CommandTable& table) {
  table.add(app.add_subcommand("components", "list the registered component types"),
            list_components);
  auto path = std::make_shared<std::string>();
  auto* graph =
      app.add_subcommand("graph", "print the composed graph of a launch file and check it");
  graph->add_option("launch", *path, "launch file (YAML)")->required()->check(CLI::ExistingFile);
  table.add(graph, [path] { return print_launch_graph(*path); });
}

}  // namespace scancrew::cli
