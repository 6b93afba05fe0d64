#pragma once

// DemoMonitor: checks the demo graph end to end. Counts the disparity estimates that
// match the camera's known disparity, the frames lost on the way (gaps in the frame
// sequence numbers), and the latency from frame publish to estimate arrival. Logs a
// summary when deactivated.

#include <cstdint>
#include <string_view>

#include "components/demo/demo_msgs.hpp"
#include "executors/component.hpp"
#include "executors/latency_histogram.hpp"
#include "executors/params.hpp"

namespace scancrew::demo {

class DemoMonitor final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "checks demo disparity estimates against the known answer; reports loss and latency";
  struct Config {
    uint32_t expected_disparity_px = 16;
  };
  static Config read_config(ParamReader& p);

  DemoMonitor(ComponentContext context, Config config);

  uint64_t received() const { return received_; }
  uint64_t correct() const { return correct_; }
  uint64_t frames_lost() const { return lost_; }

 private:
  Result<void, std::string> on_configure() override;
  void on_deactivate() override;
  void on_estimate(Sample<DisparityEstimate>&& e);

  Config config_;
  uint64_t received_ = 0, correct_ = 0, lost_ = 0, last_frame_seq_ = 0;
  LatencyHistogram end_to_end_;
};

}  // namespace scancrew::demo
