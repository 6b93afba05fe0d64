#include "components/demo/demo_monitor.hpp"

#include "executors/log.hpp"
#include "executors/registry.hpp"

namespace scancrew::demo {

DemoMonitor::Config DemoMonitor::read_config(ParamReader& p) {
  Config c;
  p.required("expected_disparity_px", c.expected_disparity_px, {1, 512})
      .doc("the disparity the estimates are checked against (px)");
  return c;
}

DemoMonitor::DemoMonitor(ComponentContext context, Config config)
    : Component(std::move(context)), config_(config) {}

Result<void, std::string> DemoMonitor::on_configure() {
  create_subscription<DisparityEstimate>(
      "disparity", {.depth = 8},
      [this](Sample<DisparityEstimate>&& e) { on_estimate(std::move(e)); });
  return {};
}

void DemoMonitor::on_estimate(Sample<DisparityEstimate>&& e) {
  ++received_;
  if (e->disparity_px == config_.expected_disparity_px) ++correct_;
  if (last_frame_seq_ != 0 && e->frame_seq > last_frame_seq_ + 1)
    lost_ += e->frame_seq - last_frame_seq_ - 1;
  last_frame_seq_ = e->frame_seq;
  end_to_end_.record(monotonic_now_ns() - e->frame_publish_mono_ns);
}

void DemoMonitor::on_deactivate() {
  SCANCREW_LOG_INFO(
      "%s: %llu estimates, %llu correct (expected %u px), %llu frames lost; "
      "frame -> estimate latency p50 %.1f us, p99 %.1f us",
      qualified_name().c_str(), static_cast<unsigned long long>(received_),
      static_cast<unsigned long long>(correct_), config_.expected_disparity_px,
      static_cast<unsigned long long>(lost_), end_to_end_.percentile_ns(0.5) * 1e-3,
      end_to_end_.percentile_ns(0.99) * 1e-3);
}

SCANCREW_REGISTER_COMPONENT(DemoMonitor, "demo_monitor")

}  // namespace scancrew::demo
