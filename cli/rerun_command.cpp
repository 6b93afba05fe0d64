// `scancrew rerun DIR [--out NEWDIR]`: repeats the run of a run directory from its own files
// (cli/run_record.hpp): launch.resolved.yaml, with run.json's --robots and --trace-events, and
// no --set (they are in the file). The input files the run read (a scene, a recording) are
// named there by absolute paths and read again, not kept: a changed scene changes the rerun.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "cli/build_info.hpp"
#include "cli/commands.hpp"
#include "cli/run_command.hpp"
#include "cli/run_record.hpp"
#include "executors/log.hpp"
#include "executors/params_impl.hpp"

namespace scancrew::cli {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

struct RerunOptions {
  std::string dir;
  std::string out_dir;  // "": <dir>_rerun
};

// DIR's run.json, or nothing after saying why.
std::optional<Json> read_record(const fs::path& dir) {
  const fs::path path = dir / kRunRecordFile;
  const auto text = read_text_file(path.string());
  if (!text) {
    std::fprintf(stderr,
                 "scancrew rerun: %s: no readable %s (%s): a run directory written by scancrew "
                 "run keeps it\n",
                 dir.c_str(), kRunRecordFile, scancrew::log::printable(text.error()).c_str());
    return std::nullopt;
  }
  try {
    Json j = Json::parse(*text);
    if (j.is_object() && j.value("process", "") == "run" && j["robots"].is_number_unsigned() &&
        j["trace_events"].is_number_unsigned())
      return j;
    if (j.is_object() && j["process"].is_string()) {
      std::fprintf(stderr,
                   "scancrew rerun: %s was run by `scancrew %s`, one process of a team split "
                   "over processes: run each process again (docs/processes.md)\n",
                   dir.c_str(), j["process"].get<std::string>().c_str());
      return std::nullopt;
    }
  } catch (const Json::exception&) {
  }
  std::fprintf(stderr,
               "scancrew rerun: %s: not a run record (JSON with process, robots and "
               "trace_events)\n",
               path.c_str());
  return std::nullopt;
}

// What differs from the first run and may change its results: said, not refused.
void note_differences(const Json& record, const fs::path& dir) {
  const std::string built =
      record.value("scancrew_version", "?") + " (commit " + record.value("git_commit", "?") + ")";
  const std::string now = scancrew_version() + " (commit " + git_commit() + ")";
  if (built != now)
    std::fprintf(stderr, "scancrew rerun: note: %s was run by scancrew %s, this is %s\n",
                 dir.c_str(), built.c_str(), now.c_str());
  std::error_code ec;
  const std::string cwd = fs::current_path(ec).string();
  if (record["cwd"].is_string() && record["cwd"].get<std::string>() != cwd)
    std::fprintf(stderr, "scancrew rerun: note: %s was run in %s; this runs in %s\n", dir.c_str(),
                 record["cwd"].get<std::string>().c_str(), cwd.c_str());
}

int rerun(const RerunOptions& o) {
  fs::path dir = fs::path(o.dir).lexically_normal();
  if (dir.filename().empty()) dir = dir.parent_path();  // "runs/x/"
  const auto record = read_record(dir);
  if (!record) return 2;
  const fs::path launch = dir / kResolvedLaunchFile;
  std::error_code ec;
  if (!fs::is_regular_file(launch, ec)) {
    std::fprintf(stderr, "scancrew rerun: %s: no %s\n", dir.c_str(), kResolvedLaunchFile);
    return 2;
  }
  const std::string out = o.out_dir.empty() ? dir.string() + "_rerun" : o.out_dir;
  if (fs::exists(out, ec) && fs::equivalent(out, dir, ec)) {
    std::fprintf(stderr, "scancrew rerun: --out %s is the run directory it repeats: give another\n",
                 out.c_str());
    return 2;
  }
  note_differences(*record, dir);
  return run_launch({.launch_path = launch.string(),
                     .out_dir = out,
                     .sets = {},
                     .robot_count = (*record)["robots"].get<size_t>(),
                     .trace_events = (*record)["trace_events"].get<size_t>(),
                     .process = "run",
                     .rerun_of = dir.string()});
}

}  // namespace

void add_rerun_command(CLI::App& app, CommandTable& table) {
  auto [cmd, options] = table.add_with_options<RerunOptions>(
      app, "rerun", "repeat the run of a run directory from its launch.resolved.yaml and run.json",
      rerun);
  cmd->add_option("dir", options->dir, "the run directory (scancrew run --out DIR)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", options->out_dir, "the new run directory (default: DIR_rerun)");
}

}  // namespace scancrew::cli
