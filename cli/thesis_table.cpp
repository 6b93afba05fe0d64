#include "cli/thesis_table.hpp"

#include <cstdio>

namespace scancrew::cli {

const std::vector<ThesisResult>& thesis_results() {
  // Table 3.2 / 4.2 rows 6, 7, 9 (SR*: noisy depth, as ours); Table 5.4 (time, total path,
  // coverage; mean over 5 trials)
  static const std::vector<ThesisResult> rows = {
      {"arena", 1, Architecture::kSingle, "5.4", 173, 20.6, 85.6},
      {"arena", 2, Architecture::kCentralized, "5.4", 165, 27.0, 80.3},
      {"arena", 2, Architecture::kDistributed, "5.4", 157, 24.2, 91.0},
      {"parking_lot", 1, Architecture::kSingle, "5.4", 836, 106.0, 89.1},
      {"parking_lot", 2, Architecture::kCentralized, "5.4", 666, 113.6, 81.1},
      {"parking_lot", 2, Architecture::kDistributed, "5.4", 641, 107.1, 88.4},
      {"parking_lot", 3, Architecture::kCentralized, "5.4", 614, 134.2, 76.4},
      {"parking_lot", 4, Architecture::kCentralized, "5.4", 576, 161.0, 73.0},
      {"powerplant", 1, Architecture::kSingle, "3.2 / 4.2 (SR*)", 1990, 785, 90.4},
      {"powerplant", 3, Architecture::kCentralized, "3.2 / 4.2 (TSGA)", 620, 790, 91.0},
      {"powerplant", 3, Architecture::kDistributed, "4.2 (dist-TSGA)", 596, 781, 95.9},
      {"powerplant", 5, Architecture::kCentralized, "3.2 / 4.2 (TSGA)", 382, 879, 90.6},
      {"powerplant", 5, Architecture::kDistributed, "4.2 (dist-TSGA)", 369, 872, 95.6},
  };
  return rows;
}

namespace {

std::string fixed(double v, int decimals) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

const ExploreRun* run_of(const std::vector<ExploreRun>& runs, const ThesisResult& t) {
  for (const ExploreRun& r : runs)
    if (r.scene == t.scene && r.robots == t.robots && r.arch == t.arch && r.ran()) return &r;
  return nullptr;
}

}  // namespace

std::string format_thesis_markdown(const std::vector<ExploreRun>& runs) {
  std::string md =
      "## Next to the thesis\n\n"
      "| scene | robots | architecture | thesis table | thesis time (s) | ours (s) | ours / "
      "thesis | thesis coverage (%) | ours coverage (%) | ours reachable (%) | thesis total "
      "path (m) | ours total path (m) |\n"
      "| --- | ---: | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const ThesisResult& t : thesis_results()) {
    const ExploreRun* r = run_of(runs, t);
    std::string ours = "not run", ratio = "—", coverage = "—", reachable = "—", path = "—";
    if (r != nullptr) {
      const bool done = r->completed();
      const double time = done ? r->completion_time_s : r->sim_time_s;
      ours = (done ? "" : "≥ ") + fixed(time, 1) + (done ? "" : " (out of time)");
      ratio = (done ? "" : "≥ ") + fixed(100.0 * time / t.time_s, 0) + " %";
      coverage = fixed(100.0 * r->coverage, 2);
      reachable = fixed(100.0 * r->coverage_reachable, 2);
      path = fixed(r->total_path_m, 1);
    }
    md += "| " + t.scene + " | " + std::to_string(t.robots) + " | " + to_string(t.arch) + " | " +
          t.table + " | " + fixed(t.time_s, 0) + " | " + ours + " | " + ratio + " | " +
          fixed(t.coverage_pct, 1) + " | " + coverage + " | " + reachable + " | " +
          fixed(t.total_path_m, 1) + " | " + path + " |\n";
  }
  md +=
      "\nThesis: Tables 3.2 and 4.2 (the powerplant, simulated UAVs with noisy depth, 10 "
      "trials) and 5.4 (the test arena and the parking lot, real ground robots with VIO "
      "poses, 5 trials; coverage by M3C2 against a scanned model). Ours: this benchmark's run "
      "(one seed), the robot kind's profile, compute charged on sim time, simulated sensors "
      "and ground-truth poses; coverage of the planning map's mesh at its own e_max "
      "(r_v·√3/2), as the thesis scores. Ground-robot coverage compares in kind only (no "
      "drift in ours). ≥: out of time at the run's budget, so the ratio is a lower bound.\n";
  return md;
}

}  // namespace scancrew::cli
