#include "components/demo/disparity_probe.hpp"

#include <cstdlib>
#include <limits>

#include "executors/registry.hpp"

namespace scancrew::demo {

DisparityProbe::Config DisparityProbe::read_config(ParamReader& p) {
  Config c;
  p.optional("max_disparity_px", c.max_disparity_px, {1, 512}).doc("largest shift searched (px)");
  p.optional("band_rows", c.band_rows, {1, 4096})
      .doc("rows around the image centre used for matching");
  return c;
}

DisparityProbe::DisparityProbe(ComponentContext context, Config config)
    : Component(std::move(context)), config_(config) {}

Result<void, std::string> DisparityProbe::on_configure() {
  estimates_ = create_publisher<DisparityEstimate>("disparity");
  create_subscription<msg::StereoFrame>(
      "stereo", {.depth = 2}, [this](Sample<msg::StereoFrame>&& f) { on_frame(std::move(f)); });
  return {};
}

int DisparityProbe::best_shift(const msg::StereoFrame& frame, uint32_t max_d, uint32_t band_rows) {
  const uint32_t w = frame.intrinsics.width, h = frame.intrinsics.height;
  if (w <= max_d || h == 0 || frame.left.size() < size_t{w} * h ||
      frame.right.size() < size_t{w} * h)
    return -1;
  const uint32_t rows = band_rows < h ? band_rows : h;
  const uint32_t y0 = (h - rows) / 2;
  int best = -1;
  uint64_t best_cost = std::numeric_limits<uint64_t>::max();
  for (uint32_t d = 0; d <= max_d; ++d) {
    uint64_t cost = 0;
    for (uint32_t y = y0; y < y0 + rows; ++y) {
      const uint8_t* l = &frame.left[size_t{y} * w];
      const uint8_t* r = &frame.right[size_t{y} * w];
      for (uint32_t x = d; x < w; ++x) cost += static_cast<uint64_t>(std::abs(l[x] - r[x - d]));
    }
    cost /= (w - d);  // per column, so large shifts are not favoured
    if (cost < best_cost) {
      best_cost = cost;
      best = static_cast<int>(d);
    }
  }
  return best;
}

void DisparityProbe::on_frame(Sample<msg::StereoFrame>&& frame) {
  const int d = best_shift(*frame, config_.max_disparity_px, config_.band_rows);
  auto loan = estimates_.loan();
  if (!loan) return;
  DisparityEstimate& e = **loan;
  e.header.stamp_ns = frame->header.stamp_ns;
  e.frame_seq = frame->header.seq;
  e.frame_publish_mono_ns = frame->header.publish_mono_ns;
  e.disparity_px = d;
  e.depth_m = d > 0 ? frame->intrinsics.fx * frame->baseline_m / d
                    : std::numeric_limits<double>::infinity();
  (void)estimates_.publish(std::move(*loan));
}

SCANCREW_REGISTER_COMPONENT(DisparityProbe, "disparity_probe")

}  // namespace scancrew::demo
