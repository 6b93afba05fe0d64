// scancrew: the command line. Each subcommand is added by the file that runs it
// (cli/commands.hpp); the benchmarks by bench/ (bench/commands.hpp).

#include <CLI/CLI.hpp>

#include "cli/build_info.hpp"
#include "cli/command_table.hpp"
#include "cli/commands.hpp"
#include "cli/run_record.hpp"
#ifdef SCANCREW_WITH_BENCH
#include "bench/commands.hpp"
#endif

int main(int argc, char** argv) {
  namespace cli = scancrew::cli;
  CLI::App app{"scancrew: multi-robot 3D reconstruction (runtime, simulator, planners)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", cli::version_text,
                       "print the version, git commit and library versions, and exit");
  cli::set_command_line(argc, argv);  // run.json keeps it
  bool parse_only = false;
  app.add_flag("--parse-only", parse_only,
               "check the command line and stop (exit 0 when it parses; runs nothing): "
               "scripts/check_results_commands.sh checks the docs' commands with it");
  cli::CommandTable table;
  cli::add_run_commands(app, table);
  cli::add_rerun_command(app, table);
  cli::add_sweep_command(app, table);
  cli::add_graph_commands(app, table);
  cli::add_render_command(app, table);
  cli::add_groundtruth_command(app, table);
  cli::add_scenegen_command(app, table);
  cli::add_eval_command(app, table);
  cli::add_keys_command(app, table);
  cli::add_report_command(app, table);
  cli::add_convert_command(app, table);

  auto* bench = app.add_subcommand("bench", "benchmarks");
  bench->require_subcommand(1);
#ifdef SCANCREW_WITH_BENCH
  scancrew::bench::add_bench_commands(*bench, table);
#else
  bench->footer("Built without the component benchmarks (SCANCREW_BUILD_BENCH=OFF): explore only.");
#endif
  cli::add_explore_command(*bench, table);

  CLI11_PARSE(app, argc, argv);
  return parse_only ? 0 : table.run_parsed();
}
