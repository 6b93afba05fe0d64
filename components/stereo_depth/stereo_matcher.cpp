#include "components/stereo_depth/stereo_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace scancrew::stereo_depth {

struct StereoMatcher::Impl {
  SgbmParams params;
  double min_range_m = 0, max_range_m = 0;
  cv::Ptr<cv::StereoSGBM> sgbm;
  double fx = 0, baseline = 0;  // the geometry sgbm was made for
  cv::Mat disparity;            // CV_16S, 4 fractional bits
  cv::Mat gradient, texture;    // CV_32F: |Sobel x| of the left image, its window mean
};

StereoMatcher::StereoMatcher(const SgbmParams& params, double min_range_m, double max_range_m)
    : impl_(std::make_unique<Impl>()) {
  impl_->params = params;
  impl_->min_range_m = min_range_m;
  impl_->max_range_m = max_range_m;
}

StereoMatcher::~StereoMatcher() = default;

uint32_t StereoMatcher::num_disparities(double fx_px, double baseline_m) const {
  if (impl_->params.num_disparities != 0) return impl_->params.num_disparities;
  // the largest disparity, at the camera's minimum range, rounded up to a multiple of 16
  // at most kMaxAutoDisparities (what num_disparities may be set to): a camera model from a
  // recording or a link asked for millions, which OpenCV then allocates per pixel
  const double d_max = std::min(fx_px * baseline_m / impl_->min_range_m, kMaxAutoDisparities);
  if (!(d_max > 0)) return 16;
  return static_cast<uint32_t>(std::ceil(d_max / 16.0)) * 16;
}

void StereoMatcher::compute(const uint8_t* left, const uint8_t* right, uint32_t width,
                            uint32_t height, double fx_px, double baseline_m,
                            std::vector<float>& depth) {
  Impl& m = *impl_;
  if (!m.sgbm || m.fx != fx_px || m.baseline != baseline_m) {
    const SgbmParams& p = m.params;
    const int block = static_cast<int>(p.block_size);
    const int p1 = p.p1 != 0 ? static_cast<int>(p.p1) : 8 * block * block;
    const int p2 = p.p2 != 0 ? static_cast<int>(p.p2) : 32 * block * block;
    int mode = cv::StereoSGBM::MODE_SGBM;
    switch (p.mode) {
      case SgbmMode::kSgbm:
        mode = cv::StereoSGBM::MODE_SGBM;
        break;
      case SgbmMode::kHh:
        mode = cv::StereoSGBM::MODE_HH;
        break;
      case SgbmMode::kSgbm3Way:
        mode = cv::StereoSGBM::MODE_SGBM_3WAY;
        break;
    }
    m.sgbm = cv::StereoSGBM::create(
        0, static_cast<int>(num_disparities(fx_px, baseline_m)), block, p1, p2, p.disp12_max_diff,
        static_cast<int>(p.pre_filter_cap), static_cast<int>(p.uniqueness_ratio),
        static_cast<int>(p.speckle_window_size), static_cast<int>(p.speckle_range), mode);
    m.fx = fx_px;
    m.baseline = baseline_m;
  }
  const int w = static_cast<int>(width), h = static_cast<int>(height);
  // cv::Mat over the message buffers: no copy (OpenCV takes non-const data pointers)
  const cv::Mat l(h, w, CV_8UC1, const_cast<uint8_t*>(left));
  const cv::Mat r(h, w, CV_8UC1, const_cast<uint8_t*>(right));
  m.sgbm->compute(l, r, m.disparity);
  // the texture check: SGBM's smoothness term carries disparities from the edges of a plain
  // face into it (right only where the face is fronto-parallel and in range); where the
  // window holds no horizontal texture there is nothing to match
  const bool check_texture = m.params.texture_threshold > 0;
  if (check_texture) {
    const int window = static_cast<int>(m.params.texture_window);
    cv::Sobel(l, m.gradient, CV_32F, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
    m.gradient = cv::abs(m.gradient);
    cv::boxFilter(m.gradient, m.texture, CV_32F, cv::Size(window, window), cv::Point(-1, -1), true,
                  cv::BORDER_REPLICATE);
  }
  const auto textured = static_cast<float>(m.params.texture_threshold);
  depth.resize(size_t{width} * height);
  const double fb = fx_px * baseline_m;
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  for (int y = 0; y < h; ++y) {
    const auto* d = m.disparity.ptr<int16_t>(y);
    const float* t = check_texture ? m.texture.ptr<float>(y) : nullptr;
    float* out = depth.data() + static_cast<size_t>(y) * width;
    for (int x = 0; x < w; ++x) {
      // no match (OpenCV marks it (min disparity - 1) * 16), or nothing to match
      if (d[x] <= 0 || (t != nullptr && t[x] < textured)) {
        out[x] = kNaN;
        continue;
      }
      const double z = fb * 16.0 / d[x];
      out[x] = (z >= m.min_range_m && z <= m.max_range_m) ? static_cast<float>(z) : kNaN;
    }
  }
}

}  // namespace scancrew::stereo_depth
