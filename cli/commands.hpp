#pragma once

// The subcommands of `scancrew`, each added by the file that runs it (cli/<name>_command.cpp)
// to the parser and to the CommandTable; the benchmarks by bench/ (bench/commands.hpp).

#include <CLI/CLI.hpp>

#include "cli/command_table.hpp"

namespace scancrew::cli {

void add_run_commands(CLI::App& app, CommandTable& table);  // run, sim, robot, station
void add_rerun_command(CLI::App& app, CommandTable& table);
void add_sweep_command(CLI::App& app, CommandTable& table);
void add_graph_commands(CLI::App& app, CommandTable& table);  // components, graph, help
void add_render_command(CLI::App& app, CommandTable& table);
void add_groundtruth_command(CLI::App& app, CommandTable& table);
void add_scenegen_command(CLI::App& app, CommandTable& table);
void add_eval_command(CLI::App& app, CommandTable& table);
void add_keys_command(CLI::App& app, CommandTable& table);  // keys init, keys add
void add_report_command(CLI::App& app, CommandTable& table);
void add_convert_command(CLI::App& app, CommandTable& table);    // .sclog to .mcap
void add_explore_command(CLI::App& bench, CommandTable& table);  // bench explore

}  // namespace scancrew::cli
