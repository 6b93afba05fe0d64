#include "components/vio/feature_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace scancrew::vio {

struct FeatureTracker::Impl {
  FeatureTrackerConfig config;
  cv::Mat previous, mask;
  std::vector<cv::Point2f> candidates, from, to;
  std::vector<uint8_t> status;
  std::vector<float> error;
  std::vector<uint32_t> cell_count;
};

namespace {

// A view of the pixels as a cv::Mat header; OpenCV only reads through it.
cv::Mat as_mat(GrayImage image) {
  return {image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data)};
}

}  // namespace

FeatureTracker::FeatureTracker(const FeatureTrackerConfig& config)
    : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
}

FeatureTracker::~FeatureTracker() = default;

void FeatureTracker::set_previous(GrayImage image) {
  as_mat(image).copyTo(impl_->previous);
}

bool FeatureTracker::has_previous() const {
  return !impl_->previous.empty();
}

void FeatureTracker::detect(std::span<const Eigen::Vector2f> keep,
                            std::vector<Eigen::Vector2f>& out) const {
  Impl& m = *impl_;
  const FeatureTrackerConfig& c = m.config;
  if (m.previous.empty() || keep.size() >= c.max_features) return;
  const size_t budget = c.max_features - keep.size();
  // mask: the border and a disc around every kept point are excluded
  m.mask.create(m.previous.size(), CV_8UC1);
  m.mask.setTo(0);
  const int border = static_cast<int>(c.border_px);
  if (m.previous.cols <= 2 * border || m.previous.rows <= 2 * border) return;
  m.mask(cv::Rect(border, border, m.previous.cols - 2 * border, m.previous.rows - 2 * border))
      .setTo(255);
  const int radius = std::max(1, static_cast<int>(std::lround(c.min_distance_px)));
  for (const Eigen::Vector2f& p : keep)
    cv::circle(
        m.mask,
        cv::Point(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y()))),
        radius, cv::Scalar(0), cv::FILLED);
  cv::goodFeaturesToTrack(m.previous, m.candidates, static_cast<int>(4 * budget), c.quality_level,
                          c.min_distance_px, m.mask, 3, false);
  // grid buckets: the best corners of each cell first, then the best of the rest
  const uint32_t cells = c.grid_cols * c.grid_rows;
  const size_t quota = (budget + cells - 1) / cells;
  m.cell_count.assign(cells, 0);
  const auto cell_of = [&](const cv::Point2f& p) {
    const auto col = std::min<uint32_t>(
        c.grid_cols - 1, static_cast<uint32_t>(p.x * static_cast<float>(c.grid_cols) /
                                               static_cast<float>(m.previous.cols)));
    const auto row = std::min<uint32_t>(
        c.grid_rows - 1, static_cast<uint32_t>(p.y * static_cast<float>(c.grid_rows) /
                                               static_cast<float>(m.previous.rows)));
    return row * c.grid_cols + col;
  };
  const size_t first = out.size();
  for (cv::Point2f& p : m.candidates) {
    uint32_t& n = m.cell_count[cell_of(p)];
    if (n >= quota) continue;
    ++n;
    out.emplace_back(p.x, p.y);
    p.x = -1;  // taken
    if (out.size() - first == budget) return;
  }
  for (const cv::Point2f& p : m.candidates) {
    if (p.x < 0) continue;
    out.emplace_back(p.x, p.y);
    if (out.size() - first == budget) return;
  }
}

size_t FeatureTracker::track(GrayImage image, std::span<const Eigen::Vector2f> from,
                             std::vector<Eigen::Vector2f>& to, std::vector<uint8_t>& ok) {
  Impl& m = *impl_;
  const FeatureTrackerConfig& c = m.config;
  const cv::Mat current = as_mat(image);
  ok.assign(from.size(), 0);
  size_t tracked = 0;
  const bool same_size = !m.previous.empty() && m.previous.size() == current.size();
  if (same_size && !from.empty() && to.size() == from.size()) {
    m.from.clear();
    m.to.clear();
    for (size_t i = 0; i < from.size(); ++i) {
      m.from.emplace_back(from[i].x(), from[i].y());
      m.to.emplace_back(to[i].x(), to[i].y());
    }
    const int window = static_cast<int>(c.klt_window_px | 1U);
    cv::calcOpticalFlowPyrLK(m.previous, current, m.from, m.to, m.status, m.error,
                             cv::Size(window, window), static_cast<int>(c.klt_levels),
                             cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                                              static_cast<int>(c.klt_iterations), 0.01),
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    const auto w = static_cast<float>(current.cols - 1), h = static_cast<float>(current.rows - 1);
    for (size_t i = 0; i < from.size(); ++i) {
      const cv::Point2f& p = m.to[i];
      to[i] = {p.x, p.y};
      if (m.status[i] == 0 || !(m.error[i] <= c.klt_max_error)) continue;
      if (!(p.x >= 0 && p.y >= 0 && p.x <= w && p.y <= h)) continue;
      ok[i] = 1;
      ++tracked;
    }
  }
  current.copyTo(m.previous);
  return tracked;
}

}  // namespace scancrew::vio
