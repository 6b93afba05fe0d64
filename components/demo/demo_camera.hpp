#pragma once

// DemoCamera: a synthetic stereo rig for the runtime demo. Publishes a random-dot
// StereoFrame at rate_hz whose right image is the left one shifted by disparity_px, so a
// downstream matcher has a known answer. The dot pattern is made once at configure();
// publishing copies it into loaned, recycled buffers (no steady-state allocation).

#include <cstdint>
#include <string_view>
#include <vector>

#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::demo {

class DemoCamera final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "synthetic random-dot stereo pair with a known disparity (runtime demo)";
  struct Config {
    double rate_hz = 30.0;
    uint32_t width = 640, height = 480;
    uint32_t disparity_px = 16;
    double fx_px = 320.0;
    double baseline_m = 0.26;
    uint64_t seed = 1;
  };
  static Config read_config(ParamReader& p);

  DemoCamera(ComponentContext context, Config config);

 private:
  Result<void, std::string> on_configure() override;
  void capture();

  Config config_;
  Publisher<msg::StereoFrame> frames_;
  std::vector<uint8_t> pattern_;  // (width + disparity) x height
  uint64_t frame_ = 0;
  uint64_t loan_failures_ = 0;
};

}  // namespace scancrew::demo
