#pragma once

// The output of `scancrew bench tsdf` (tsdf_bench.hpp) beyond its rows: the issue's
// targets checked against the rows, and the table printed without --json.

#include <nlohmann/json.hpp>

namespace scancrew::bench {

using Json = nlohmann::ordered_json;

// Appends to out["targets"] one line per target of the issue that out["results"] and
// out["comparisons"] can decide: ≤ 10 ms per 640 × 480 frame at 0.1 m and 5 m (scancrew),
// and ≥ 2× faster than Open3D at equal or better coverage and RMSE.
void add_targets(Json& out);

// scancrew's and Open3D's rows side by side, one line per configuration, with the speedup
// (Open3D's ms per frame over scancrew's), then the target lines.
void print_table(const Json& out);

}  // namespace scancrew::bench
