// `scancrew components [NAME]`: the registered component types, or one type's parameters
// (cli/param_reference.hpp; --markdown: docs/parameters.md). `scancrew graph <launch.yaml>`:
// the composed graph of a launch file, and its checks. `scancrew help [COMMAND...]`: the
// command list, or a command's help (CLI11's, as --help prints it).

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/param_reference.hpp"
#include "cli/report.hpp"
#include "cli/run_command.hpp"
#include "executors/registry.hpp"

namespace scancrew::cli {

namespace {

struct ComponentsOptions {
  std::string type;
  bool markdown = false;
};

int list_components(const ComponentsOptions& o) {
  const auto& registry = ComponentRegistry::instance();
  if (o.markdown) {
    std::fputs(parameters_markdown().c_str(), stdout);
    return 0;
  }
  if (o.type.empty()) {
    for (const auto& type : registry.types())
      std::printf("%-24s %s\n", type.c_str(), registry.find(type)->description.c_str());
    return 0;
  }
  const ComponentRegistry::Entry* entry = registry.find(o.type);
  if (entry == nullptr) {
    std::string known;
    for (const auto& type : registry.types()) known += (known.empty() ? "" : ", ") + type;
    std::fprintf(stderr, "no component type '%s'; known: %s\n", o.type.c_str(), known.c_str());
    return 2;
  }
  std::fputs(parameter_text(o.type, entry->description, registry.parameters(o.type)).c_str(),
             stdout);
  return 0;
}

// `help`: the root's help (the command list), or that of the command the words name.
int print_help(const CLI::App& root, const std::vector<std::string>& words) {
  const CLI::App* command = &root;
  std::string name = "scancrew";
  for (const std::string& word : words) {
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : command->get_subcommands({}))
      if (sub->get_name() == word) next = sub;
    if (next == nullptr) {
      std::fprintf(stderr, "no command '%s %s'; `scancrew help` lists them\n", name.c_str(),
                   word.c_str());
      return 2;
    }
    command = next;
    name += " " + word;
  }
  // the formatter directly: App::help() would describe the parsed `help` command itself
  std::fputs(command->get_formatter()->make_help(command, name, CLI::AppFormatMode::Normal).c_str(),
             stdout);
  return 0;
}

// --dot: Graphviz's DOT instead of the text (`scancrew graph F --dot | dot -Tsvg > g.svg`)
int print_launch_graph(const std::string& path, bool dot) {
  auto launch = compose_or_report(path, {});
  if (!launch) return 2;
  if (dot)
    print_graph_dot(stdout, *launch, path);
  else
    print_graph(stdout, *launch);
  return launch->report().errors.empty() ? 0 : 2;
}

}  // namespace

void add_graph_commands(CLI::App& app, CommandTable& table) {
  auto [components, options] = table.add_with_options<ComponentsOptions>(
      app, "components",
      "list the registered component types, or one type's parameters (type, default, range, "
      "description)",
      list_components);
  components->add_option("name", options->type, "a component type: print its parameters");
  components->add_flag("--markdown", options->markdown,
                       "print every type's parameters as Markdown (docs/parameters.md)");
  auto path = std::make_shared<std::string>();
  auto* graph =
      app.add_subcommand("graph", "print the composed graph of a launch file and check it");
  graph->add_option("launch", *path, "launch file (YAML)")->required()->check(CLI::ExistingFile);
  auto dot = std::make_shared<bool>(false);
  graph->add_flag("--dot", *dot, "print the graph in Graphviz's DOT language (pipe to dot -Tsvg)");
  table.add(graph, [path, dot] { return print_launch_graph(*path, *dot); });
  auto words = std::make_shared<std::vector<std::string>>();
  auto* help = app.add_subcommand("help", "print the commands, or a command's help");
  help->add_option("command", *words, "a command (and subcommand), e.g. run, bench explore");
  table.add(help, [&app, words] { return print_help(app, *words); });
}

}  // namespace scancrew::cli
