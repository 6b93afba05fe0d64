#include "components/vio/sparse_stereo.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace scancrew::vio {

struct SparseStereo::Impl {
  SparseStereoConfig config;
  cv::Mat cost;
  std::vector<StereoPoint> candidates;
  std::vector<cv::Point2f> left_px, right_px;
  std::vector<uint8_t> status;
  std::vector<float> error;
};

namespace {

cv::Mat as_mat(GrayImage image) {
  return {image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data)};
}

// Offset of the minimum of the parabola through (-1, a), (0, b), (1, c), in [-0.5, 0.5].
float parabola_offset(float a, float b, float c) {
  const float den = a - 2 * b + c;
  if (!(den > 0)) return 0;
  return std::clamp(0.5F * (a - c) / den, -0.5F, 0.5F);
}

}  // namespace

SparseStereo::SparseStereo(const SparseStereoConfig& config) : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
}

SparseStereo::~SparseStereo() = default;

size_t SparseStereo::match(GrayImage left, GrayImage right, const msg::CameraIntrinsics& intrinsics,
                           double baseline_m, std::span<const Eigen::Vector2f> corners,
                           std::vector<StereoPoint>& out) {
  Impl& m = *impl_;
  const SparseStereoConfig& c = m.config;
  const cv::Mat l = as_mat(left), r = as_mat(right);
  const int half = static_cast<int>(c.window_px / 2);
  const int window = 2 * half + 1;
  const int half_rows = static_cast<int>(c.window_rows / 2);
  const int rows = 2 * half_rows + 1;
  const double fb = intrinsics.fx * baseline_m;
  const int d_min = std::max(0, static_cast<int>(std::floor(fb / c.max_depth_m)));
  const int d_max_all = static_cast<int>(std::ceil(fb / c.min_depth_m));
  m.candidates.clear();
  // block matching along the row
  for (const Eigen::Vector2f& corner : corners) {
    const int x = static_cast<int>(std::lround(corner.x()));
    const int y = static_cast<int>(std::lround(corner.y()));
    if (y - half_rows < 0 || y + half_rows >= l.rows || x - half < 0 || x + half >= l.cols)
      continue;
    const int d_max = std::min(d_max_all, x - half);
    if (d_max - d_min < 2) continue;
    const cv::Mat templ = l(cv::Rect(x - half, y - half_rows, window, rows));
    // right-image centres x - d_max .. x - d_min
    const cv::Mat strip =
        r(cv::Rect(x - d_max - half, y - half_rows, d_max - d_min + window, rows));
    cv::matchTemplate(strip, templ, m.cost, cv::TM_SQDIFF);
    const auto* cost = m.cost.ptr<float>(0);
    const int n = m.cost.cols;  // index k: disparity d_max - k
    int best = 0;
    for (int k = 1; k < n; ++k)
      if (cost[k] < cost[best]) best = k;
    float second = std::numeric_limits<float>::infinity();
    for (int k = 0; k < n; ++k)
      if (std::abs(k - best) > 2) second = std::min(second, cost[k]);
    if (!(cost[best] < c.uniqueness_ratio * second)) continue;
    if (best == 0 || best == n - 1) continue;  // at the edge of the search: out of range
    const float offset = parabola_offset(cost[best - 1], cost[best], cost[best + 1]);
    // disparity grows as k shrinks
    const float disparity = static_cast<float>(d_max - best) - offset;
    m.candidates.push_back({corner, Eigen::Vector3d::Zero(), disparity});
  }
  // sub-pixel refinement: KLT on the full-resolution pair, starting at the match
  if (c.klt_refine && !m.candidates.empty()) {
    m.left_px.clear();
    m.right_px.clear();
    for (const StereoPoint& s : m.candidates) {
      m.left_px.emplace_back(s.left_px.x(), s.left_px.y());
      m.right_px.emplace_back(s.left_px.x() - s.disparity_px, s.left_px.y());
    }
    cv::calcOpticalFlowPyrLK(
        l, r, m.left_px, m.right_px, m.status, m.error, cv::Size(window, rows), 0,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.01),
        cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t i = 0; i < m.candidates.size(); ++i) {
      StereoPoint& s = m.candidates[i];
      const float guess = s.left_px.x() - s.disparity_px;
      const cv::Point2f& p = m.right_px[i];
      if (m.status[i] == 0 || std::abs(p.y - s.left_px.y()) > c.max_row_error_px ||
          std::abs(p.x - guess) > c.max_refine_shift_px) {
        s.disparity_px = 0;  // rejected
        continue;
      }
      s.disparity_px = s.left_px.x() - p.x;
    }
  }
  // triangulation
  size_t added = 0;
  for (StereoPoint& s : m.candidates) {
    if (!(s.disparity_px > 0)) continue;
    const double z = fb / s.disparity_px;
    if (z < c.min_depth_m || z > c.max_depth_m) continue;
    s.p_cam = {(s.left_px.x() - intrinsics.cx) * z / intrinsics.fx,
               (s.left_px.y() - intrinsics.cy) * z / intrinsics.fy, z};
    out.push_back(s);
    ++added;
  }
  return added;
}

}  // namespace scancrew::vio
