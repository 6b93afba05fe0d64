#pragma once

// TSPLIB instances (Reinelt 1991, "TSPLIB - A Traveling Salesman Problem Library") of the
// explicit full-matrix kind: TYPE ATSP (or TSP), EDGE_WEIGHT_TYPE EXPLICIT,
// EDGE_WEIGHT_FORMAT FULL_MATRIX, then DIMENSION^2 numbers in EDGE_WEIGHT_SECTION, row by
// row, across any line breaks, and an optional EOF. The benchmark's instances are in
// data/tsplib_atsp/ (data/tsplib_atsp/ATTRIBUTION.md).
//
// Errors name the source and the line: "ftv33.atsp:12: 'x7' is not a number". Values
// must be finite (TSPLIB marks forbidden arcs with large numbers, e.g. 9999 on the
// diagonal, which the solvers never read).

#include <istream>
#include <string>

#include "core/result.hpp"
#include "core/tsga/atsp.hpp"

namespace scancrew::tsga {

struct TsplibInstance {
  std::string name;
  std::string comment;
  CostMatrix costs;
};

// The largest DIMENSION accepted (the matrix is held in full).
inline constexpr size_t kMaxTsplibDimension = 4096;

// source names the input in error messages (a path, or "<inline>").
Result<TsplibInstance, std::string> parse_tsplib(std::istream& in, const std::string& source);
Result<TsplibInstance, std::string> load_tsplib(const std::string& path);

}  // namespace scancrew::tsga
