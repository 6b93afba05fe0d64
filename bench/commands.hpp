#pragma once

// The benchmarks' subcommands of `scancrew bench`, registered here so that the CLI names none
// of them (cli/commands.hpp). Built with SCANCREW_BUILD_BENCH (the default).

#include <CLI/CLI.hpp>

#include "cli/command_table.hpp"

namespace scancrew::bench {

// ipc, sim, perception, tsdf, ise, tsp, planner, dds, pipeline under `bench`.
void add_bench_commands(CLI::App& bench, cli::CommandTable& table);

}  // namespace scancrew::bench
