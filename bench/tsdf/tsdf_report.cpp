#include "bench/tsdf/tsdf_report.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace scancrew::bench {

void add_targets(Json& out) {
  for (const Json& r : out["results"])
    if (r["system"] == "scancrew" && r["width"] == 640 && r["height"] == 480 &&
        r["voxel_m"] == 0.1 && r["range_m"] == 5.0) {
      const double ms = r["ms_per_frame"].get<double>();
      char line[160];
      std::snprintf(line, sizeof line,
                    "target <= 10 ms per 640x480 frame at 0.1 m, 5 m: %.2f ms (%s)", ms,
                    ms <= 10 ? "met" : "missed");
      out["targets"].push_back(line);
    }
  if (!out["comparisons"].empty()) {
    size_t faster = 0, accurate = 0, both = 0;
    for (const Json& c : out["comparisons"]) {
      faster += c["at_least_2x_faster"].get<bool>() ? 1 : 0;
      accurate += c["equal_or_better_accuracy"].get<bool>() ? 1 : 0;
      both +=
          c["at_least_2x_faster"].get<bool>() && c["equal_or_better_accuracy"].get<bool>() ? 1 : 0;
    }
    char line[200];
    std::snprintf(
        line, sizeof line,
        "target >= 2x faster than Open3D at equal or better coverage and RMSE: met in %zu "
        "of %zu configurations (2x faster: %zu; coverage and RMSE as good: %zu)",
        both, out["comparisons"].size(), faster, accurate);
    out["targets"].push_back(line);
  }
}

void print_table(const Json& out) {
  const Json& results = out["results"];
  auto find = [&](const Json& ours) -> const Json* {
    for (const Json& r : results)
      if (r["system"] == "open3d" && r["width"] == ours["width"] && r["height"] == ours["height"] &&
          r["voxel_m"] == ours["voxel_m"] && r["range_m"] == ours["range_m"])
        return &r;
    return nullptr;
  };
  auto cells = [](const Json& r) {
    std::printf(" %8.2f %7.1f %6.1f %7.1f %7.1f |", r["ms_per_frame"].get<double>(),
                r["mesh_ms"].get<double>(), 100 * r["coverage"].get<double>(),
                r["rmse_m"].is_number() ? 1e3 * r["rmse_m"].get<double>() : NAN,
                1e-3 * r["bytes_per_m2"].get<double>());
  };
  std::printf(
      "TSDF on %s: %d frames per size, fastest of %d runs; threads: scancrew %d (TBB), Open3D "
      "%d (OpenMP)\n",
      out["scene"].get<std::string>().c_str(), out["frames"].get<int>(), out["repeats"].get<int>(),
      out["threads"]["scancrew_tbb"].get<int>(), out["threads"]["open3d_openmp"].get<int>());
  std::printf("ground truth: %zu points over %.0f m2; coverage is of the whole scene\n\n",
              out["ground_truth"]["points"].get<size_t>(),
              out["ground_truth"]["area_m2"].get<double>());
  std::printf(
      "%21s| %-40s| %-40s|\n", "", "scancrew",
      out["open3d"].get<std::string>() == "unavailable" ? "open3d (unavailable)" : "open3d");
  std::printf("%-8s %5s %5s |", "size", "voxel", "range");
  for (int i = 0; i < 2; ++i)
    std::printf(" %8s %7s %6s %7s %7s |", "ms/frame", "mesh_ms", "cov_%", "rmse_mm", "kB/m2");
  std::printf(" %s\n", "speedup");
  for (const Json& r : results) {
    if (r["system"] != "scancrew") continue;
    char size[32];
    std::snprintf(size, sizeof size, "%dx%d", r["width"].get<int>(), r["height"].get<int>());
    std::printf("%-8s %5.1f %5.1f |", size, r["voxel_m"].get<double>(), r["range_m"].get<double>());
    cells(r);
    if (const Json* peer = find(r); peer != nullptr) {
      cells(*peer);
      std::printf(" %6.2fx\n",
                  (*peer)["ms_per_frame"].get<double>() / r["ms_per_frame"].get<double>());
    } else {
      std::printf(" %39s | %s\n", "-", "-");
    }
  }
  for (const Json& line : out["targets"]) std::printf("\n%s", line.get<std::string>().c_str());
  std::printf("\n");
}

}  // namespace scancrew::bench
