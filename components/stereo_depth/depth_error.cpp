#include "components/stereo_depth/depth_error.hpp"

#include <algorithm>
#include <cmath>

namespace scancrew::stereo_depth {

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

void DepthErrorAccumulator::add(const std::vector<float>& estimate, const std::vector<float>& truth,
                                double min_range_m, double max_range_m) {
  const size_t n = std::min(estimate.size(), truth.size());
  for (size_t i = 0; i < n; ++i) {
    const double t = truth[i];
    if (!std::isfinite(t) || t < min_range_m || t > max_range_m) continue;
    ++reference_;
    const double e = estimate[i];
    if (!std::isfinite(e)) continue;
    abs_.push_back(std::abs(e - t));
    rel_.push_back(std::abs(e - t) / t);
  }
}

DepthError DepthErrorAccumulator::result(double outlier_rel) const {
  DepthError r;
  r.reference_pixels = reference_;
  r.valid_pixels = abs_.size();
  r.valid_ratio =
      reference_ ? static_cast<double>(abs_.size()) / static_cast<double>(reference_) : 0;
  r.median_abs_m = median(abs_);
  r.median_rel = median(rel_);
  const auto outliers =
      std::count_if(rel_.begin(), rel_.end(), [&](double e) { return e > outlier_rel; });
  r.outlier_ratio =
      rel_.empty() ? 0 : static_cast<double>(outliers) / static_cast<double>(rel_.size());
  return r;
}

DepthError depth_error(const std::vector<float>& estimate, const std::vector<float>& truth,
                       double min_range_m, double max_range_m, double outlier_rel) {
  DepthErrorAccumulator acc;
  acc.add(estimate, truth, min_range_m, max_range_m);
  return acc.result(outlier_rel);
}

}  // namespace scancrew::stereo_depth
