#include "cli/explore_table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <tuple>

namespace scancrew::cli {

namespace {

// started by no benchmark yet (stopped before its turn, or --report)
bool not_run(const ExploreRun& r) {
  return r.exit_status == -1 && r.error.empty() && !r.ran();
}

using Json = nlohmann::ordered_json;

double number(const Json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : kNoValue;
}

Json number_or_null(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

std::string csv_number(double v) {
  if (!std::isfinite(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

struct Row {
  std::string family;
  Architecture arch = Architecture::kSingle;
  size_t robots = 0;
  size_t runs = 0, completed = 0, ran = 0, not_run = 0, reached90 = 0, reached95 = 0;
  bool lower_bound = false;
  std::vector<double> time, t90, t95, coverage, reachable, rmse, path, contacts, idle;
};

std::vector<Row> aggregate(const std::vector<ExploreRun>& runs) {
  std::vector<Row> rows;
  std::map<std::tuple<std::string, size_t, Architecture>, size_t> index;
  for (const ExploreRun& r : runs) {
    const auto [it, added] =
        index.emplace(std::make_tuple(r.family, r.robots, r.arch), rows.size());
    if (added) rows.push_back({.family = r.family, .arch = r.arch, .robots = r.robots});
    Row& row = rows[it->second];
    ++row.runs;
    if (not_run(r)) ++row.not_run;
    if (!r.ran()) continue;
    ++row.ran;
    if (r.completed()) {
      ++row.completed;
      row.time.push_back(r.completion_time_s);
    } else {
      row.lower_bound = true;
      row.time.push_back(r.sim_time_s);
    }
    if (std::isfinite(r.t90_reachable_s)) {
      ++row.reached90;
      row.t90.push_back(r.t90_reachable_s);
    }
    if (std::isfinite(r.t95_reachable_s)) {
      ++row.reached95;
      row.t95.push_back(r.t95_reachable_s);
    }
    row.coverage.push_back(100 * r.coverage);
    row.reachable.push_back(100 * r.coverage_reachable);
    row.rmse.push_back(1000 * r.rmse_m);
    row.path.push_back(r.total_path_m);
    row.contacts.push_back(r.contacts);
    row.idle.push_back(100 * r.idle_share);
  }
  return rows;
}

std::string mean_cell(const std::vector<double>& values, int decimals) {
  return format_mean_std(mean_std(values), decimals);
}

// the mean of the runs that reached it, and how many of the row's runs did
std::string reached_cell(const std::vector<double>& values, size_t reached, size_t ran) {
  if (reached == 0) return "—";
  std::string cell = format_mean_std(mean_std(values), 0);
  if (reached < ran) cell += " (" + std::to_string(reached) + "/" + std::to_string(ran) + ")";
  return cell;
}

}  // namespace

Result<ExploreRun, std::string> read_explore_metrics(std::string_view json_text, ExploreRun run,
                                                     const std::string& label) {
  // what a sweep reads too, then what only the benchmark does
  auto common = read_sweep_metrics(json_text, SweepRun{}, label);
  if (!common) return make_unexpected(common.error());
  run.stop_reason = common->stop_reason;
  run.error.clear();
  run.completion_time_s = common->completion_time_s;
  run.sim_time_s = common->sim_time_s;
  run.wall_time_s = common->wall_time_s;
  run.coverage = common->coverage;
  run.coverage_reachable = common->coverage_reachable;
  run.rmse_m = common->rmse_m;
  run.total_path_m = common->total_path_length_m;
  run.contacts = static_cast<double>(common->collisions);
  run.idle_share = common->idle_share;
  run.t95_reachable_s = common->time_to_95_reachable_s;
  run.compute_time = common->compute_time;
  const Json j = Json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (const auto t = j.find("time_to_coverage_reachable_s"); t != j.end() && t->is_object())
    run.t90_reachable_s = number(*t, "90");
  if (const auto places = j.find("places"); places != j.end() && places->is_array())
    for (const Json& p : *places)
      if (const auto name = p.find("place"); name != p.end() && name->is_string())
        run.places.push_back(name->get<std::string>());
  if (const auto robots = j.find("robots"); robots != j.end() && robots->is_array()) {
    double sum = 0;
    size_t n = 0;
    for (const Json& r : *robots) {
      const auto t = r.find("time_s");
      if (t == r.end() || !t->is_object()) continue;
      for (const auto& [k, v] : t->items()) sum += v.is_number() ? v.get<double>() : 0;
      ++n;
    }
    if (n > 0) run.breakdown_sum_s = sum / static_cast<double>(n);
  }
  return run;
}

std::string check_explore_run(const ExploreRun& r) {
  const std::string who = r.scene + " " + to_string(r.arch) + " " + std::to_string(r.robots) + ": ";
  if (!r.ran()) return who + "did not run (" + r.error + ")";
  if (r.exit_status != 0 && r.exit_status != 3)
    return who + "scancrew run exited with status " + std::to_string(r.exit_status);
  if (!(r.coverage >= 0 && r.coverage <= 1)) return who + "coverage missing or outside [0, 1]";
  if (!(r.coverage_reachable >= 0 && r.coverage_reachable <= 1))
    return who + "coverage_reachable missing or outside [0, 1]";
  if (!std::isfinite(r.breakdown_sum_s) || !std::isfinite(r.sim_time_s) ||
      std::abs(r.breakdown_sum_s - r.sim_time_s) > 0.01 * r.sim_time_s + 0.05)
    return who + "the time breakdown (" + csv_number(r.breakdown_sum_s) +
           " s) does not sum to the mission time (" + csv_number(r.sim_time_s) + " s)";
  if (r.compute_time != "charged")
    return who + "compute_time is '" + r.compute_time + "', not charged";
  if (r.arch == Architecture::kSingle &&
      std::find(r.places.begin(), r.places.end(), "station") != r.places.end())
    return who + "a single robot's compute was charged on a ground station (run.station)";
  return {};
}

std::string format_explore_csv(const std::vector<ExploreRun>& runs) {
  std::string csv =
      "scene,family,kind,arch,robots,budget_s,stop_reason,exit_status,completion_time_s,"
      "sim_time_s,wall_time_s,t90_reachable_s,t95_reachable_s,coverage,coverage_reachable,"
      "rmse_m,total_path_m,contacts,idle_share,compute_time,run_dir\n";
  for (const ExploreRun& r : runs) {
    const std::vector<std::string> f = {r.scene,
                                        r.family,
                                        robot::to_string(r.kind),
                                        to_string(r.arch),
                                        std::to_string(r.robots),
                                        csv_number(r.budget_s),
                                        not_run(r) ? "not_run" : to_string(r.stop_reason),
                                        std::to_string(r.exit_status),
                                        csv_number(r.completion_time_s),
                                        csv_number(r.sim_time_s),
                                        csv_number(r.wall_time_s),
                                        csv_number(r.t90_reachable_s),
                                        csv_number(r.t95_reachable_s),
                                        csv_number(r.coverage),
                                        csv_number(r.coverage_reachable),
                                        csv_number(r.rmse_m),
                                        csv_number(r.total_path_m),
                                        csv_number(r.contacts),
                                        csv_number(r.idle_share),
                                        r.compute_time,
                                        r.run_dir};
    for (size_t i = 0; i < f.size(); ++i) csv += (i > 0 ? "," : "") + f[i];
    csv += "\n";
  }
  return csv;
}

std::string format_explore_markdown(const std::vector<ExploreRun>& runs, const std::string& title,
                                    const std::string& command, const std::string& machine) {
  std::string md = "# " + title + "\n\n";
  if (!command.empty()) md += "Command: `" + command + "`  \n";
  if (!machine.empty()) md += "Machine: " + machine + "\n";
  md +=
      "\n| family | robots | architecture | completed / runs | time (s) | 90 % reachable (s) | "
      "95 % reachable (s) | coverage (%) | reachable (%) | RMSE (mm) | total path (m) | "
      "contacts | idle (%) |\n"
      "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: "
      "|\n";
  bool lower_bound = false;
  for (const Row& row : aggregate(runs)) {
    lower_bound = lower_bound || row.lower_bound;
    std::string runs_cell = std::to_string(row.completed) + "/" + std::to_string(row.runs);
    const size_t failed = row.runs - row.ran - row.not_run;
    if (failed > 0) runs_cell += " (" + std::to_string(failed) + " failed)";
    if (row.not_run > 0) runs_cell += " (" + std::to_string(row.not_run) + " not run yet)";
    md += "| " + row.family + " | " + std::to_string(row.robots) + " | " + to_string(row.arch) +
          " | " + runs_cell + " | " + (row.lower_bound ? "≥ " : "") + mean_cell(row.time, 1) +
          " | " + reached_cell(row.t90, row.reached90, row.ran) + " | " +
          reached_cell(row.t95, row.reached95, row.ran) + " | " + mean_cell(row.coverage, 2) +
          " | " + mean_cell(row.reachable, 2) + " | " + mean_cell(row.rmse, 1) + " | " +
          mean_cell(row.path, 1) + " | " + mean_cell(row.contacts, 1) + " | " +
          mean_cell(row.idle, 0) + " |\n";
  }
  md +=
      "\nMean ± standard deviation over the family's scenes (one run each). Time: simulated "
      "seconds, compute charged (docs/runtime.md), to the ISE criterion. 90 % / 95 % reachable: "
      "the first time the monitor's estimate of the coverage of the reachable surface reached "
      "it, over the runs that did (k/n when not all). Coverage: the final mesh against all the "
      "ground truth, and against what the team's robot kinds can observe (docs/evaluation.md). "
      "Contacts: robot-scene and robot-robot. Idle: the robots' mean share of the mission "
      "idle.\n";
  if (lower_bound)
    md +=
        "\n≥: a run of the row did not complete by its budget; its simulated time stands for "
        "its completion time, so the mean is a lower bound.\n";
  return md;
}

std::string format_explore_json(const std::vector<ExploreRun>& runs) {
  Json out;
  Json list = Json::array();
  for (const ExploreRun& r : runs)
    list.push_back({{"scene", r.scene},
                    {"family", r.family},
                    {"kind", robot::to_string(r.kind)},
                    {"arch", to_string(r.arch)},
                    {"robots", r.robots},
                    {"budget_s", r.budget_s},
                    {"stop_reason", to_string(r.stop_reason)},
                    {"exit_status", r.exit_status},
                    {"completion_time_s", number_or_null(r.completion_time_s)},
                    {"sim_time_s", number_or_null(r.sim_time_s)},
                    {"wall_time_s", number_or_null(r.wall_time_s)},
                    {"t90_reachable_s", number_or_null(r.t90_reachable_s)},
                    {"t95_reachable_s", number_or_null(r.t95_reachable_s)},
                    {"coverage", number_or_null(r.coverage)},
                    {"coverage_reachable", number_or_null(r.coverage_reachable)},
                    {"rmse_m", number_or_null(r.rmse_m)},
                    {"total_path_m", number_or_null(r.total_path_m)},
                    {"contacts", number_or_null(r.contacts)},
                    {"idle_share", number_or_null(r.idle_share)},
                    {"run_dir", r.run_dir}});
  out["runs"] = std::move(list);
  Json rows = Json::array();
  for (const Row& row : aggregate(runs))
    rows.push_back({{"family", row.family},
                    {"robots", row.robots},
                    {"arch", to_string(row.arch)},
                    {"runs", row.runs},
                    {"completed", row.completed},
                    {"time_s", number_or_null(mean_std(row.time).mean)},
                    {"time_is_lower_bound", row.lower_bound},
                    {"t95_reachable_s", number_or_null(mean_std(row.t95).mean)},
                    {"coverage_reachable", number_or_null(mean_std(row.reachable).mean / 100)},
                    {"idle_share", number_or_null(mean_std(row.idle).mean / 100)}});
  out["rows"] = std::move(rows);
  return out.dump(2) + "\n";
}

}  // namespace scancrew::cli
