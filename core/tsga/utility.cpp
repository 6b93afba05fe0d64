#include "core/tsga/utility.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace scancrew::tsga {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string number(double v) {
  if (std::isnan(v)) return "NaN";
  return std::to_string(v);
}

Result<void, std::string> check_lengths(const CostMatrix& m, const char* what) {
  for (size_t i = 0; i < m.size(); ++i) {
    for (size_t j = 0; j < m.size(); ++j) {
      const double v = m(i, j);
      if (i != j && !(v >= 0.0))  // also refuses NaN
        return make_unexpected(std::string(what) + " (" + std::to_string(i) + ", " +
                               std::to_string(j) + ") is " + number(v) +
                               "; allowed: >= 0 or +infinity (unreachable)");
    }
  }
  return {};
}

}  // namespace

Result<CostMatrix, std::string> utility_matrix(std::span<const uint64_t> ids,
                                               std::span<const double> gains,
                                               const CostMatrix& inter_m, const CostMatrix& intra_m,
                                               const UtilityWeights& weights) {
  const size_t n = ids.size();
  if (gains.size() != n || inter_m.size() != n || intra_m.size() != n)
    return make_unexpected("utility_matrix: " + std::to_string(n) + " ids, " +
                           std::to_string(gains.size()) + " gains, " +
                           std::to_string(inter_m.size()) + " x " + std::to_string(inter_m.size()) +
                           " inter lengths and " + std::to_string(intra_m.size()) + " x " +
                           std::to_string(intra_m.size()) + " intra lengths; all must agree");
  for (const double lambda : {weights.lambda_tc_per_m, weights.lambda_ic_per_m})
    if (!(lambda >= 0.0) || !std::isfinite(lambda))
      return make_unexpected(
          "utility_matrix: lambda_tc_per_m and lambda_ic_per_m must be finite "
          "and >= 0; got " +
          number(weights.lambda_tc_per_m) + " and " + number(weights.lambda_ic_per_m));
  // duplicate ids: sort the indices by id and compare neighbours
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return ids[a] < ids[b] || (ids[a] == ids[b] && a < b); });
  for (size_t p = 1; p < n; ++p)
    if (ids[order[p]] == ids[order[p - 1]])
      return make_unexpected(
          "utility_matrix: duplicate cluster id " + std::to_string(ids[order[p]]) + " (nodes " +
          std::to_string(order[p - 1]) + " and " + std::to_string(order[p]) + ")");
  for (size_t i = 0; i < n; ++i)
    if (!(gains[i] >= 0.0) || !std::isfinite(gains[i]))
      return make_unexpected("utility_matrix: gain of cluster " + std::to_string(ids[i]) + " is " +
                             number(gains[i]) + "; allowed: finite, >= 0");
  if (auto ok = check_lengths(inter_m, "inter-cluster length"); !ok)
    return make_unexpected("utility_matrix: " + ok.error());
  if (auto ok = check_lengths(intra_m, "intra-cluster length"); !ok)
    return make_unexpected("utility_matrix: " + ok.error());

  CostMatrix f(n, 0.0);
  for (size_t u = 0; u < n; ++u) {
    for (size_t v = 0; v < n; ++v) {
      if (u == v) continue;
      const double d_tc = inter_m(u, v);
      const double d_ic = intra_m(u, v);
      f(u, v) = (d_tc == kInf || d_ic == kInf)
                    ? -kInf
                    : gains[v] * std::exp(-weights.lambda_tc_per_m * d_tc -
                                          weights.lambda_ic_per_m * d_ic);
    }
  }
  return f;
}

}  // namespace scancrew::tsga
