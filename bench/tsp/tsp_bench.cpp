#include "bench/tsp/tsp_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <string_view>
#include <vector>

#include "core/tsga/atsp.hpp"
#include "core/tsga/tsga_planner.hpp"
#include "core/tsga/tsplib.hpp"
#include "core/tsga/utility.hpp"

namespace scancrew::bench {

namespace {

using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;

struct KnownOptimum {
  const char* name;
  double optimum;
};

// data/tsplib_atsp/ATTRIBUTION.md
constexpr KnownOptimum kOptima[] = {
    {"br17", 39},    {"ftv33", 1286},    {"ftv38", 1530},  {"ftv47", 1776},
    {"ft53", 6905},  {"ftv55", 1608},    {"ftv64", 1839},  {"ft70", 38673},
    {"ftv70", 1950}, {"kro124p", 36230}, {"ftv170", 2755},
};
constexpr std::string_view kQuickInstances[] = {"br17", "ftv33", "ftv38"};

// the targets
constexpr double kMeanGapTargetPct = 1.0;
constexpr double kSmallGapTargetPct = 0.2;
constexpr size_t kSmallMaxNodes = 71;
constexpr double kInstanceTargetMs = 1000.0;
constexpr double kMaxAtspTargetMs = 20.0;
constexpr int kMaxAtspTargetClusters = 100;
constexpr double kTsgaTargetMs = 200.0;  // TSGA, 200 clusters to 5 robots
constexpr int kTsgaClusters = 200;
constexpr int kTsgaRobots = 5;
// the long maxATSP reference run: this many times the default kicks
constexpr int kLongRunFactor = 20;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// eq. 2.3 over random clusters; node 0 is the robot ({q_0}, gain 0)
tsga::CostMatrix random_utilities(size_t clusters, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const size_t n = clusters + 1;
  std::vector<double> x(n);
  std::vector<double> y(n);
  std::vector<double> z(n);
  std::vector<double> gains(n, 0.0);
  std::vector<double> intra_m(n, 0.0);
  std::vector<uint64_t> ids(n);
  for (size_t i = 0; i < n; ++i) {
    x[i] = 65.0 * u01(rng);
    y[i] = 42.0 * u01(rng);
    z[i] = 15.0 * u01(rng);
    ids[i] = i;
    if (i > 0) {
      gains[i] = 0.01 + 0.2 * u01(rng);
      intra_m[i] = 10.0 * u01(rng);
    }
  }
  tsga::CostMatrix inter(n, 0.0);
  tsga::CostMatrix intra(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) {
      inter(i, j) = std::hypot(x[i] - x[j], y[i] - y[j], z[i] - z[j]);
      intra(i, j) = intra_m[j];
    }
  }
  return tsga::utility_matrix(ids, gains, inter, intra, {0.1, 0.1}).value();
}

Json target(const std::string& what, double value, double limit, const char* unit) {
  Json t;
  t["target"] = what;
  t["value"] = value;
  t["limit"] = limit;
  t["unit"] = unit;
  t["met"] = value <= limit;
  return t;
}

void print_table(const Json& out) {
  const auto& o = out["options"];
  std::printf(
      "TSPLIB ATSP, closed tours (seed %llu, %d kicks per node, time limit %.0f ms, one "
      "thread)\n",
      static_cast<unsigned long long>(o["seed"].get<uint64_t>()), o["kicks_per_node"].get<int>(),
      o["time_limit_ms"].get<double>());
  std::printf("%-9s %4s %9s %9s %7s %9s %7s  %s\n", "instance", "n", "optimum", "found", "gap %",
              "ms", "kicks", "status");
  for (const auto& r : out["instances"])
    std::printf("%-9s %4d %9.0f %9.0f %7.3f %9.1f %7d  %s\n", r["name"].get<std::string>().c_str(),
                r["n"].get<int>(), r["optimum"].get<double>(), r["found"].get<double>(),
                r["gap_pct"].get<double>(), r["ms"].get<double>(), r["kicks"].get<int>(),
                r["status"].get<std::string>().c_str());
  std::printf("\nmaxATSP, eq. 2.3 utilities (default SolverOptions: %d kicks)\n",
              o["max_atsp_kicks"].get<int>());
  std::printf("%8s %5s %9s %8s %8s  %s\n", "clusters", "nodes", "instances", "mean ms", "max ms",
              "utility vs 20x kicks");
  for (const auto& r : out["max_atsp"]) {
    std::printf("%8d %5d %9d %8.2f %8.2f  ", r["clusters"].get<int>(), r["nodes"].get<int>(),
                r["instances"].get<int>(), r["ms_mean"].get<double>(), r["ms_max"].get<double>());
    if (r.contains("gap_vs_long_pct"))
      std::printf("-%.3f %%\n", r["gap_vs_long_pct"].get<double>());
    else
      std::printf("not measured (--quick)\n");
  }
  std::printf("\nintra-cluster paths (open path over a cluster's viewpoints, best of 3)\n");
  std::printf("%10s %5s %8s %9s\n", "viewpoints", "kicks", "ms", "length m");
  for (const auto& r : out["intra_paths"])
    std::printf("%10d %5d %8.2f %9.2f\n", r["viewpoints"].get<int>(), r["kicks"].get<int>(),
                r["ms"].get<double>(), r["length_m"].get<double>());
  std::printf("\ntargets\n");
  for (const auto& t : out["targets"])
    std::printf("  %-52s %9.3f %-3s (limit %g): %s\n", t["target"].get<std::string>().c_str(),
                t["value"].get<double>(), t["unit"].get<std::string>().c_str(),
                t["limit"].get<double>(), t["met"].get<bool>() ? "met" : "MISSED");
}

// What the TSPLIB runs add up to, for the targets.
struct TsplibSummary {
  double gap_sum = 0.0;
  double small_worst = 0.0;
  double worst_ms = 0.0;
  int instances = 0;
};

// Solves each TSPLIB instance (the quick ones only with --quick) and appends its row to
// out["instances"]; nullopt (after a message) when an instance cannot be read or solved.
std::optional<TsplibSummary> bench_tsplib(const TspBenchOptions& options, Json& out) {
  tsga::SolverOptions tsplib_options;
  tsplib_options.seed = options.seed;
  tsplib_options.time_limit_ms = kInstanceTargetMs;
  TsplibSummary sum;
  for (const auto& known : kOptima) {
    if (options.quick && std::find(std::begin(kQuickInstances), std::end(kQuickInstances),
                                   known.name) == std::end(kQuickInstances))
      continue;
    auto instance = tsga::load_tsplib(options.dir + "/" + known.name + ".atsp");
    if (!instance) {
      std::fprintf(stderr,
                   "bench tsp: %s (--dir: the folder of the .atsp files; default: "
                   "data/tsplib_atsp under the repository root)\n",
                   instance.error().c_str());
      return std::nullopt;
    }
    const size_t n = instance->costs.size();
    tsplib_options.max_iterations = options.kicks_per_node * static_cast<int>(n);
    const auto t0 = Clock::now();
    auto tour = tsga::solve_closed_atsp(instance->costs, tsplib_options);
    const double ms = ms_since(t0);
    if (!tour) {
      std::fprintf(stderr, "bench tsp: %s: %s\n", known.name, tour.error().c_str());
      return std::nullopt;
    }
    const double gap = 100.0 * (tour->cost - known.optimum) / known.optimum;
    Json row;
    row["name"] = known.name;
    row["n"] = n;
    row["optimum"] = known.optimum;
    row["found"] = tour->cost;
    row["gap_pct"] = gap;
    row["ms"] = ms;
    row["kicks"] = tour->iterations;
    row["status"] = std::string(tsga::to_string(tour->status));
    out["instances"].push_back(row);
    sum.gap_sum += gap;
    if (n <= kSmallMaxNodes) sum.small_worst = std::max(sum.small_worst, gap);
    sum.worst_ms = std::max(sum.worst_ms, ms);
    ++sum.instances;
  }
  return sum;
}

// Times maxATSP on random eq. 2.3 utilities of 50, 100 and 200 clusters and sets
// out["max_atsp"]; the mean ms at kMaxAtspTargetClusters, or nullopt (after a message) when
// a solve fails.
std::optional<double> bench_max_atsp(const TspBenchOptions& options,
                                     const tsga::SolverOptions& planner_options, Json& out) {
  out["max_atsp"] = Json::array();
  const int repeats = options.quick ? std::min(options.repeats, 2) : options.repeats;
  double ms_at_target = 0.0;
  for (int clusters : {50, 100, 200}) {
    double ms_sum = 0.0;
    double ms_max = 0.0;
    double gap_long = 0.0;
    for (int r = 0; r < repeats; ++r) {
      const auto utility = random_utilities(static_cast<size_t>(clusters),
                                            static_cast<uint32_t>(1000 * clusters + r));
      const auto t0 = Clock::now();
      auto path = tsga::solve_max_open_path(utility, 0, planner_options);
      const double ms = ms_since(t0);
      if (!path) {
        std::fprintf(stderr, "bench tsp: maxATSP: %s\n", path.error().c_str());
        return std::nullopt;
      }
      ms_sum += ms;
      ms_max = std::max(ms_max, ms);
      if (!options.quick) {
        tsga::SolverOptions long_options = planner_options;
        long_options.max_iterations *= kLongRunFactor;
        long_options.time_limit_ms = 0.0;
        auto best = tsga::solve_max_open_path(utility, 0, long_options);
        if (best) gap_long += 100.0 * (best->utility - path->utility) / best->utility;
      }
    }
    Json row;
    row["clusters"] = clusters;
    row["nodes"] = clusters + 1;
    row["instances"] = repeats;
    row["ms_mean"] = ms_sum / repeats;
    row["ms_max"] = ms_max;
    if (!options.quick) row["gap_vs_long_pct"] = gap_long / repeats;
    out["max_atsp"].push_back(row);
    if (clusters == kMaxAtspTargetClusters) ms_at_target = ms_sum / repeats;
  }
  return ms_at_target;
}

// n_clusters clusters of 1-4 viewpoints over a 60 x 40 m floor, drawn from seed.
std::vector<tsga::PlanCluster> random_clusters(int n_clusters, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> x(0, 60), y(0, 40), gain(0.001, 0.02), jitter(-1, 1);
  std::uniform_int_distribution<int> count(1, 4);
  std::vector<tsga::PlanCluster> clusters;
  for (int i = 0; i < n_clusters; ++i) {
    tsga::PlanCluster c;
    c.id = static_cast<uint32_t>(i);
    c.gain = gain(rng);
    const Eigen::Vector3d centre(x(rng), y(rng), 0.35);
    for (int k = count(rng); k > 0; --k)
      c.viewpoints.push_back(centre + Eigen::Vector3d(jitter(rng), jitter(rng), 0));
    clusters.push_back(std::move(c));
  }
  return clusters;
}

// Times TSGA (best of 3, one with --quick) on random clusters and kTsgaRobots robots in a
// row and sets out["tsga"]; the best ms, or nullopt (after a message) when planning fails.
std::optional<double> bench_tsga(const TspBenchOptions& options, Json& out) {
  const int n_clusters = options.quick ? 40 : kTsgaClusters;
  const std::vector<tsga::PlanCluster> clusters = random_clusters(n_clusters, options.seed);
  std::vector<tsga::PlanRobot> robots;
  robots.reserve(kTsgaRobots);
  for (int i = 0; i < kTsgaRobots; ++i)
    robots.push_back({.id = static_cast<uint32_t>(i + 1),
                      .position = Eigen::Vector3d(5.0 + 12.5 * i, 2.0, 0.35)});
  tsga::PlannerOptions planner;
  planner.seed = options.seed;
  double best = 1e300;
  size_t assigned = 0;
  for (int r = 0; r < (options.quick ? 1 : 3); ++r) {
    const auto t0 = Clock::now();
    auto plan = tsga::plan_tsga(robots, clusters, planner);
    const double ms = ms_since(t0);
    if (!plan) {
      std::fprintf(stderr, "bench tsp: TSGA: %s\n", plan.error().c_str());
      return std::nullopt;
    }
    best = std::min(best, ms);
    assigned = 0;
    for (const auto& robot : plan->robots) assigned += robot.clusters.size();
  }
  out["tsga"] = {{"clusters", n_clusters},
                 {"robots", kTsgaRobots},
                 {"assigned", assigned},
                 {"ms", best},
                 {"insertion_kicks", planner.insertion_iterations},
                 {"final_kicks", planner.final_iterations}};
  return best;
}

// Times the shortest open path over 100 (300, 600) random viewpoints, best of 3, and sets
// out["intra_paths"]; false (after a message) when a solve fails.
bool bench_intra_paths(const TspBenchOptions& options, Json& out) {
  out["intra_paths"] = Json::array();
  const tsga::PlannerOptions defaults;
  for (const int n : options.quick ? std::vector<int>{100} : std::vector<int>{100, 300, 600}) {
    std::mt19937_64 rng(options.seed + static_cast<uint64_t>(n));
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Eigen::Vector3d> p(static_cast<size_t>(n));
    for (Eigen::Vector3d& v : p) v = Eigen::Vector3d(60 * u(rng), 1.5 * u(rng), 15 * u(rng));
    tsga::CostMatrix costs(static_cast<size_t>(n) + 1, 0.0);
    for (size_t a = 0; a < p.size(); ++a)
      for (size_t b = 0; b < p.size(); ++b) costs(a, b) = (p[a] - p[b]).norm();
    tsga::SolverOptions so;
    so.max_iterations = defaults.insertion_iterations;
    so.seed = options.seed;
    double best = 1e300, length = 0;
    for (int r = 0; r < 3; ++r) {
      const auto t0 = Clock::now();
      auto tour = tsga::solve_closed_atsp(costs, so);
      const double ms = ms_since(t0);
      if (!tour) {
        std::fprintf(stderr, "bench tsp: intra-cluster path: %s\n", tour.error().c_str());
        return false;
      }
      best = std::min(best, ms);
      length = tour->cost;
    }
    out["intra_paths"].push_back(
        {{"viewpoints", n}, {"kicks", so.max_iterations}, {"ms", best}, {"length_m", length}});
  }
  return true;
}

}  // namespace

int run_tsp_bench(const TspBenchOptions& options) {
  Json out;
  out["instances"] = Json::array();

  // 1. TSPLIB, closed tours
  const auto tsplib = bench_tsplib(options, out);
  if (!tsplib) return 2;

  // 2. maxATSP with the planners' default options
  tsga::SolverOptions planner_options;
  planner_options.seed = options.seed;
  const auto ms_at_target = bench_max_atsp(options, planner_options, out);
  if (!ms_at_target) return 2;

  // 3. TSGA (Algorithm 2): 200 clusters of 1-4 viewpoints over a 60 x 40 m floor, 5 robots,
  //    the planners' default options
  const auto tsga_ms = bench_tsga(options, out);
  if (!tsga_ms) return 2;

  // 4. intra-cluster paths (the TSGA planner's τ_lm): the shortest open path over a
  //    cluster's viewpoints, a closed ATSP with a free dummy node, with the insertion budget.
  //    Viewpoints spread over a 60 x 1.5 x 15 m slab, as along a facade: the powerplant's
  //    largest clusters hold hundreds (docs/tsga.md, "Planning time on large maps").
  if (!bench_intra_paths(options, out)) return 2;

  // 5. targets
  const std::string over = std::to_string(tsplib->instances) + " instances";
  out["targets"] = Json::array({
      target("mean gap over the " + over, tsplib->gap_sum / std::max(tsplib->instances, 1),
             kMeanGapTargetPct, "%"),
      target("worst gap for n <= 71", tsplib->small_worst, kSmallGapTargetPct, "%"),
      target("slowest instance", tsplib->worst_ms, kInstanceTargetMs, "ms"),
      target("maxATSP on 100 clusters, mean", *ms_at_target, kMaxAtspTargetMs, "ms"),
      target(
          "TSGA, " + std::to_string(out["tsga"]["clusters"].get<int>()) + " clusters to 5 robots",
          *tsga_ms, kTsgaTargetMs, "ms"),
  });
  out["options"] = {{"dir", options.dir},
                    {"quick", options.quick},
                    {"seed", options.seed},
                    {"kicks_per_node", options.kicks_per_node},
                    {"time_limit_ms", kInstanceTargetMs},
                    {"max_atsp_kicks", planner_options.max_iterations}};
  if (options.json)
    std::printf("%s\n", out.dump().c_str());
  else
    print_table(out);
  return 0;
}

}  // namespace scancrew::bench
