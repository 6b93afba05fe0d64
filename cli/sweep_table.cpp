#include "cli/sweep_table.hpp"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <tuple>

namespace scancrew::cli {

namespace {

using Json = nlohmann::json;

double number_at(const Json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : kNoValue;
}

uint64_t count_at(const Json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number()) return 0;
  if (it->is_number_unsigned()) return it->get<uint64_t>();
  const double v = it->get<double>();
  return v > 0 ? static_cast<uint64_t>(v) : 0;
}

std::string printf_string(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// a CSV field: quoted when it holds a comma, a quote or a line break (RFC 4180)
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

std::string csv_number(double v) {
  return std::isfinite(v) ? printf_string("%.10g", v) : "";
}

// a Markdown table cell: no '|' or line break may break the row
std::string md_cell(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n' || c == '\r')
      out += ' ';
    else
      out += c;
  }
  return out;
}

// `text`, as code in Markdown
std::string md_code(const std::string& text) {
  std::string s = "`";
  s += md_cell(text);
  s += '`';
  return s;
}

std::string runs_cell(const SweepRow& row) {
  std::string s = std::to_string(row.completed) + "/" + std::to_string(row.runs);
  if (row.failed > 0) s += " (" + std::to_string(row.failed) + " failed)";
  if (row.interrupted > 0) s += " (" + std::to_string(row.interrupted) + " interrupted)";
  return s;
}

// "72 / 16 / 0 / 0 / 1 / 11 / 0 / 0": the activities' mean shares (%), "—" without any.
std::string shares_cell(const SweepRow& row) {
  std::string cell;
  for (size_t a = 0; a < row.time_share_pct.size(); ++a) {
    const MeanStd& s = row.time_share_pct[a];
    if (s.n == 0) return "—";
    char buf[16];
    std::snprintf(buf, sizeof buf, "%.0f", s.mean);
    cell += (a > 0 ? " / " : "") + std::string(buf);
  }
  return cell;
}

std::string ratio_cell(const TimeRatio& r) {
  switch (r.bound) {
    case TimeRatio::Bound::kExact:
      return printf_string("%.0f %%", r.percent);
    case TimeRatio::Bound::kAtMost:
      return "≤ " + printf_string("%.0f %%", r.percent);
    case TimeRatio::Bound::kAtLeast:
      return "≥ " + printf_string("%.0f %%", r.percent);
    case TimeRatio::Bound::kUnknown:
      break;
  }
  return "—";
}

// the row time vs 1 robot is measured against (null: none in the scene)
const SweepRow* reference_row(const std::vector<SweepRow>& rows, const SweepRow& row) {
  const SweepRow* own_arch = nullptr;
  for (const SweepRow& r : rows) {
    if (r.scene != row.scene || r.robots != 1) continue;
    if (r.arch == Architecture::kSingle) return &r;
    if (r.arch == row.arch) own_arch = &r;
  }
  return own_arch;
}

}  // namespace

Result<SweepRun, std::string> read_sweep_metrics(std::string_view json_text, SweepRun run,
                                                 const std::string& label) {
  const Json j = Json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) return make_unexpected(label + ": not a JSON object");
  const auto reason = j.find("stop_reason");
  if (reason == j.end() || !reason->is_string()) return make_unexpected(label + ": no stop_reason");
  const std::string reason_name = reason->get<std::string>();
  const auto stop_reason = value_of(kStopReasonNames, reason_name);
  if (!stop_reason)
    return make_unexpected(label + ": stop_reason '" + reason_name +
                           "' is not allowed; allowed: " + joined_names(kStopReasonNames));
  run.stop_reason = *stop_reason;
  run.error.clear();
  if (const auto scene = j.find("scene"); scene != j.end() && scene->is_string())
    run.scene = scene->get<std::string>();
  run.completion_time_s = number_at(j, "completion_time_s");
  run.sim_time_s = number_at(j, "sim_time_s");
  run.wall_time_s = number_at(j, "wall_time_s");
  run.coverage = number_at(j, "coverage");
  run.mean_error_m = number_at(j, "mean_error_m");
  run.rmse_m = number_at(j, "rmse_m");
  run.total_path_length_m = number_at(j, "total_path_length_m");
  run.data_exchanged_bytes = number_at(j, "data_exchanged_bytes");
  run.collisions = count_at(j, "collisions");
  run.replans = count_at(j, "replans");
  run.coverage_reachable = number_at(j, "coverage_reachable");
  run.idle_share = number_at(j, "idle_share");
  run.tours_per_goal = number_at(j, "tours_per_goal");
  run.m_per_goal = number_at(j, "m_per_goal");
  if (const auto t = j.find("time_share"); t != j.end() && t->is_object())
    for (size_t a = 0; a < report::kActivityCount; ++a)
      run.time_share[a] =
          number_at(*t, std::string(report::to_string(report::Activity(a))).c_str());
  if (const auto t = j.find("time_to_coverage_reachable_s"); t != j.end() && t->is_object())
    run.time_to_95_reachable_s = number_at(*t, "95");
  if (const auto c = j.find("compute_time"); c != j.end() && c->is_string())
    run.compute_time = c->get<std::string>();
  return run;
}

RunOutcome outcome_of(const SweepRun& run) {
  switch (run.stop_reason) {
    case StopReason::kComplete:
      return RunOutcome::kComplete;
    case StopReason::kInterrupted:
      return RunOutcome::kInterrupted;
    case StopReason::kFailed:
      return RunOutcome::kFailed;
    case StopReason::kStalled:
    case StopReason::kTimeBudget:
      break;
  }
  return RunOutcome::kIncomplete;
}

MeanStd mean_std(const std::vector<double>& values) {
  MeanStd s;
  double sum = 0;
  for (const double v : values)
    if (std::isfinite(v)) {
      sum += v;
      ++s.n;
    }
  if (s.n == 0) return s;
  s.mean = sum / static_cast<double>(s.n);
  double squares = 0;
  for (const double v : values)
    if (std::isfinite(v)) squares += (v - s.mean) * (v - s.mean);
  s.std = s.n > 1 ? std::sqrt(squares / static_cast<double>(s.n - 1)) : 0.0;
  return s;
}

std::vector<SweepRow> aggregate_sweep(const std::vector<SweepRun>& runs) {
  // a failed run has no metrics.json, hence no scene: its architecture's
  std::map<Architecture, std::string> scene_of_arch;
  for (const SweepRun& r : runs)
    if (!r.scene.empty()) scene_of_arch.emplace(r.arch, r.scene);

  struct Values {
    std::vector<double> time, coverage, rmse, path, data, reachable, idle, t95, tours, m_goal;
    std::array<std::vector<double>, report::kActivityCount> share;
  };
  std::vector<SweepRow> rows;
  std::vector<Values> values;
  std::map<std::tuple<std::string, Architecture, size_t>, size_t> index;
  for (const SweepRun& r : runs) {
    std::string scene = r.scene;
    if (scene.empty())
      if (const auto it = scene_of_arch.find(r.arch); it != scene_of_arch.end()) scene = it->second;
    const auto [it, added] = index.emplace(std::make_tuple(scene, r.arch, r.robots), rows.size());
    if (added) {
      rows.push_back({.scene = scene, .arch = r.arch, .robots = r.robots});
      values.emplace_back();
    }
    SweepRow& row = rows[it->second];
    Values& v = values[it->second];
    ++row.runs;
    const RunOutcome outcome = outcome_of(r);
    switch (outcome) {
      case RunOutcome::kComplete:
        ++row.completed;
        v.time.push_back(std::isfinite(r.completion_time_s) ? r.completion_time_s : r.sim_time_s);
        break;
      case RunOutcome::kIncomplete:
        ++row.incomplete;
        v.time.push_back(r.sim_time_s);
        row.time_is_lower_bound = row.time_is_lower_bound || std::isfinite(r.sim_time_s);
        break;
      case RunOutcome::kInterrupted:
        ++row.interrupted;
        break;
      case RunOutcome::kFailed:
        ++row.failed;
        break;
    }
    if (outcome == RunOutcome::kComplete || outcome == RunOutcome::kIncomplete) {
      v.coverage.push_back(100.0 * r.coverage);
      v.rmse.push_back(1000.0 * r.rmse_m);
      v.path.push_back(r.total_path_length_m);
      v.data.push_back(r.data_exchanged_bytes / 1e6);
      v.reachable.push_back(100.0 * r.coverage_reachable);
      v.idle.push_back(100.0 * r.idle_share);
      v.t95.push_back(r.time_to_95_reachable_s);
      v.tours.push_back(r.tours_per_goal);
      v.m_goal.push_back(r.m_per_goal);
      for (size_t a = 0; a < report::kActivityCount; ++a)
        v.share[a].push_back(100.0 * r.time_share[a]);
      row.collisions += r.collisions;
    }
  }
  for (size_t i = 0; i < rows.size(); ++i) {
    rows[i].time_s = mean_std(values[i].time);
    rows[i].coverage_pct = mean_std(values[i].coverage);
    rows[i].rmse_mm = mean_std(values[i].rmse);
    rows[i].path_m = mean_std(values[i].path);
    rows[i].data_mb = mean_std(values[i].data);
    rows[i].coverage_reachable_pct = mean_std(values[i].reachable);
    rows[i].idle_pct = mean_std(values[i].idle);
    rows[i].t95_reachable_s = mean_std(values[i].t95);
    rows[i].tours_per_goal = mean_std(values[i].tours);
    rows[i].m_per_goal = mean_std(values[i].m_goal);
    for (size_t a = 0; a < report::kActivityCount; ++a)
      rows[i].time_share_pct[a] = mean_std(values[i].share[a]);
  }
  return rows;
}

TimeRatio time_ratio(const SweepRow& row, const SweepRow& reference) {
  TimeRatio r;
  if (row.time_s.n == 0 || reference.time_s.n == 0 || !(reference.time_s.mean > 0)) return r;
  if (row.time_is_lower_bound && reference.time_is_lower_bound) return r;
  r.percent = 100.0 * row.time_s.mean / reference.time_s.mean;
  r.bound = row.time_is_lower_bound         ? TimeRatio::Bound::kAtLeast
            : reference.time_is_lower_bound ? TimeRatio::Bound::kAtMost
                                            : TimeRatio::Bound::kExact;
  return r;
}

std::string format_mean_std(const MeanStd& value, int decimals) {
  if (value.n == 0) return "—";
  char buf[96];
  if (value.n == 1)
    std::snprintf(buf, sizeof buf, "%.*f", decimals, value.mean);
  else
    std::snprintf(buf, sizeof buf, "%.*f ± %.*f", decimals, value.mean, decimals, value.std);
  return buf;
}

std::string format_sweep_csv(const std::vector<SweepRun>& runs) {
  std::string csv =
      "arch,robots,seed,stop_reason,completion_time_s,sim_time_s,wall_time_s,coverage,"
      "mean_error_m,rmse_m,total_path_length_m,data_exchanged_bytes,collisions,replans,"
      "coverage_reachable,idle_share,time_to_95_reachable_s,tours_per_goal,m_per_goal,";
  for (size_t a = 0; a < report::kActivityCount; ++a)
    csv += "share_" + std::string(report::to_string(report::Activity(a))) + ",";
  csv += "compute_time,scene,run_dir,error\n";
  for (const SweepRun& r : runs) {
    const bool measured = outcome_of(r) != RunOutcome::kFailed;
    std::vector<std::string> fields = {
        csv_field(to_string(r.arch)),
        std::to_string(r.robots),
        std::to_string(r.seed),
        csv_field(to_string(r.stop_reason)),
        csv_number(r.completion_time_s),
        csv_number(r.sim_time_s),
        csv_number(r.wall_time_s),
        csv_number(r.coverage),
        csv_number(r.mean_error_m),
        csv_number(r.rmse_m),
        csv_number(r.total_path_length_m),
        csv_number(r.data_exchanged_bytes),
        measured ? std::to_string(r.collisions) : "",
        measured ? std::to_string(r.replans) : "",
        csv_number(r.coverage_reachable),
        csv_number(r.idle_share),
        csv_number(r.time_to_95_reachable_s),
        csv_number(r.tours_per_goal),
        csv_number(r.m_per_goal),
    };
    for (const double share : r.time_share) fields.push_back(csv_number(share));
    fields.insert(fields.end(), {csv_field(r.compute_time), csv_field(r.scene),
                                 csv_field(r.run_dir), csv_field(r.error)});
    for (size_t i = 0; i < fields.size(); ++i) csv += (i > 0 ? "," : "") + fields[i];
    csv += "\n";
  }
  return csv;
}

std::string format_sweep_markdown(const std::vector<SweepRun>& runs, const std::string& title) {
  const std::vector<SweepRow> rows = aggregate_sweep(runs);
  std::string md = "# " + title + "\n";
  std::vector<std::string> scenes;
  for (const SweepRow& r : rows)
    if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
  for (const std::string& scene : scenes) {
    md += "\n## Scene ";
    md += scene.empty() ? std::string("(unknown: no run has metrics)") : md_code(scene);
    md += "\n\n";
    md +=
        "| architecture | robots | completed / runs | time (s) | time vs 1 robot | "
        "coverage (%) | reachable (%) | 95 % reachable (s) | RMSE (mm) | total path (m) | "
        "data exchanged (MB) | tours / goal | m / goal | time: drive / turn / traffic / wait / "
        "back off / idle open / idle done / lost (%) | collisions |\n";
    md +=
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
        "---: | ---: | ---: |\n";
    bool lower_bound = false, left_out = false;
    for (const SweepRow& row : rows) {
      if (row.scene != scene) continue;
      lower_bound = lower_bound || row.time_is_lower_bound;
      left_out = left_out || row.failed > 0 || row.interrupted > 0;
      const SweepRow* ref = reference_row(rows, row);
      const std::string ratio = ref == &row      ? "ref."
                                : ref == nullptr ? "—"
                                                 : ratio_cell(time_ratio(row, *ref));
      const std::string time =
          (row.time_is_lower_bound ? "≥ " : "") + format_mean_std(row.time_s, 1);
      md += "| " + md_cell(to_string(row.arch)) + " | " + std::to_string(row.robots) + " | " +
            runs_cell(row) + " | " + time + " | " + ratio + " | " +
            format_mean_std(row.coverage_pct, 2) + " | " +
            format_mean_std(row.coverage_reachable_pct, 2) + " | " +
            format_mean_std(row.t95_reachable_s, 0) + " | " + format_mean_std(row.rmse_mm, 1) +
            " | " + format_mean_std(row.path_m, 1) + " | " + format_mean_std(row.data_mb, 2) +
            " | " + format_mean_std(row.tours_per_goal, 1) + " | " +
            format_mean_std(row.m_per_goal, 1) + " | " + shares_cell(row) + " | " +
            std::to_string(row.collisions) + " |\n";
    }
    md +=
        "\nMean ± standard deviation (n − 1) over the seeds; time: the simulated time at which "
        "the mission completed. Time vs 1 robot: the row's mean time in % of the single "
        "robot's (ref.; without a single-architecture row, the same architecture's with 1 "
        "robot). Reachable: coverage of the surface the team's robot kinds can observe "
        "(docs/evaluation.md); 95 % reachable: when the monitor's estimate of it reached "
        "95 %, over the runs that reached it. Tours / goal: tours planned per goal reached "
        "(plan churn); m / goal: metres driven per goal reached. Time: the robots' mean "
        "shares of the mission (docs/missions.md, \"Where the time goes\"), means over the "
        "runs. Collisions: robot-scene and robot-robot contacts, summed over the runs.\n";
    if (lower_bound)
      md +=
          "\n≥: a run of the row did not complete (time budget or stall); its simulated time "
          "stands for its completion time, so the mean is a lower bound, and a ratio against "
          "it is marked ≥ (or ≤ when the reference is the lower bound).\n";
    if (left_out)
      md +=
          "\nFailed runs (no metrics.json) and interrupted runs (Ctrl-C) count in \"runs\" "
          "only.\n";
  }
  return md;
}

}  // namespace scancrew::cli
