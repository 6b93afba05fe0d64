#include "components/demo/demo_camera.hpp"

#include <chrono>
#include <cstring>
#include <random>

#include "executors/registry.hpp"

namespace scancrew::demo {

DemoCamera::Config DemoCamera::read_config(ParamReader& p) {
  Config c;
  p.optional("rate_hz", c.rate_hz, {0.1, 1000}).doc("frame rate (Hz)");
  p.optional("width", c.width, {16, 8192}).doc("image width (px)");
  p.optional("height", c.height, {16, 8192}).doc("image height (px)");
  p.optional("disparity_px", c.disparity_px, {1, 256})
      .doc("the known disparity of the random-dot pair (px)");
  p.optional("fx_px", c.fx_px, {1, 1e5}).doc("focal length of the intrinsics it sends (px)");
  p.optional("baseline_m", c.baseline_m, {1e-3, 10}).doc("stereo baseline it sends (m)");
  p.optional("seed", c.seed).doc("random seed of the dots");
  return c;
}

DemoCamera::DemoCamera(ComponentContext context, Config config)
    : Component(std::move(context)), config_(config) {}

Result<void, std::string> DemoCamera::on_configure() {
  frames_ = create_publisher<msg::StereoFrame>("stereo");
  std::mt19937_64 rng(config_.seed);
  std::uniform_int_distribution<int> dot(0, 255);
  pattern_.resize(static_cast<size_t>(config_.width + config_.disparity_px) * config_.height);
  for (auto& px : pattern_) px = static_cast<uint8_t>(dot(rng));
  create_timer(std::chrono::nanoseconds(static_cast<int64_t>(1e9 / config_.rate_hz)),
               [this] { capture(); });
  return {};
}

void DemoCamera::capture() {
  auto loan = frames_.loan();
  if (!loan) {
    ++loan_failures_;  // counted by the topic too; the next tick tries again
    return;
  }
  msg::StereoFrame& f = **loan;
  const uint32_t w = config_.width, h = config_.height, d = config_.disparity_px;
  f.intrinsics = {w, h, config_.fx_px, config_.fx_px, w / 2.0, h / 2.0};
  f.baseline_m = config_.baseline_m;
  f.left.resize(static_cast<size_t>(w) * h);
  f.right.resize(static_cast<size_t>(w) * h);
  // left(x) = P(x), right(x) = P(x + d): a point at left column x is at x - d on the right
  const uint32_t stride = w + d;
  for (uint32_t y = 0; y < h; ++y) {
    const uint8_t* row = pattern_.data() + static_cast<size_t>(y) * stride;
    std::memcpy(&f.left[static_cast<size_t>(y) * w], row, w);
    std::memcpy(&f.right[static_cast<size_t>(y) * w], row + d, w);
  }
  ++frame_;
  (void)frames_.publish(std::move(*loan));
}

SCANCREW_REGISTER_COMPONENT(DemoCamera, "demo_camera")

}  // namespace scancrew::demo
