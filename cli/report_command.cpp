// `scancrew report <run_dir>`: a mission run directory's pictures and report.html, written
// again from its files (report/run_report.hpp).

#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "executors/log.hpp"
#include "report/run_report.hpp"

namespace scancrew::cli {

namespace {

int write_report(const std::string& run_dir) {
  const auto written = report::write_report(run_dir);
  if (!written) {
    std::fprintf(stderr, "scancrew report: %s\n", log::printable(written.error()).c_str());
    return 1;
  }
  std::printf("report: %s/report.html\n", run_dir.c_str());
  return 0;
}

}  // namespace

void add_report_command(CLI::App& app, CommandTable& table) {
  auto run_dir = std::make_shared<std::string>();
  auto* report = app.add_subcommand(
      "report", "write a mission run directory's pictures and report.html (docs/missions.md)");
  report->add_option("run_dir", *run_dir, "run directory (scancrew run ... --out DIR)")->required();
  table.add(report, [run_dir] { return write_report(*run_dir); });
}

}  // namespace scancrew::cli
