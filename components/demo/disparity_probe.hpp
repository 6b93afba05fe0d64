#pragma once

// DisparityProbe: finds the one horizontal shift that best aligns a stereo pair (sum of
// absolute differences over a band of rows) and publishes it with the depth f·B/d.
// A stand-in for real stereo matching (step 3) that gives the demo graph real work and
// a checkable answer.

#include <string_view>

#include "components/demo/demo_msgs.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::demo {

class DisparityProbe final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "block-matches a band of a stereo pair to find its global disparity (runtime demo)";
  struct Config {
    uint32_t max_disparity_px = 64;
    uint32_t band_rows = 32;  // rows around the image centre used for matching
  };
  static Config read_config(ParamReader& p);

  DisparityProbe(ComponentContext context, Config config);

  // SAD-minimising shift d in [0, max_d] with left(x) ~ right(x - d); -1 if the images
  // are too small. Pure function, exposed for tests.
  static int best_shift(const msg::StereoFrame& frame, uint32_t max_d, uint32_t band_rows);

 private:
  Result<void, std::string> on_configure() override;
  void on_frame(Sample<msg::StereoFrame>&& frame);

  Config config_;
  Publisher<DisparityEstimate> estimates_;
};

}  // namespace scancrew::demo
