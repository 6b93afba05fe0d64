#pragma once

// CommandTable: the subcommands of `scancrew` and what each runs. Every command file adds its
// own subcommand to the CLI11 parser, binds the options to storage its run function owns, and
// enters the pair here (cli/*_command.cpp; the benchmarks from bench/, bench/commands.hpp).
// main() parses and runs the one that was parsed. The idea of rclcpp's component registration
// (a type names itself where it is defined) applied to commands: main() lists no command.

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace scancrew::cli {

class CommandTable {
 public:
  // `run` gives the process's exit status; it is called when `command` was parsed.
  void add(CLI::App* command, std::function<int()> run) {
    entries_.emplace_back(command, std::move(run));
  }

  // Adds a subcommand of `parent` whose options live in an Options value owned by the table;
  // returns the subcommand and that value, for the caller to declare the options on.
  template <class Options>
  std::pair<CLI::App*, Options*> add_with_options(CLI::App& parent, const std::string& name,
                                                  const std::string& description,
                                                  int (*run)(const Options&)) {
    auto options = std::make_shared<Options>();
    CLI::App* command = parent.add_subcommand(name, description);
    add(command, [options, run] { return run(*options); });
    return {command, options.get()};
  }

  // The exit status of the parsed command's run; 1 when no entered command was parsed.
  int run_parsed() const {
    for (const auto& [command, run] : entries_)
      if (command->parsed()) return run();
    return 1;
  }

 private:
  std::vector<std::pair<CLI::App*, std::function<int()>>> entries_;
};

}  // namespace scancrew::cli
