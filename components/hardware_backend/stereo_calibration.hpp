#pragma once

// StereoCalibration: a calibrated stereo pair as read from a calibration file. The file
// holds what OpenCV's stereoCalibrate() returns (K, D per camera; R, T between them), in
// the format documented in docs/hardware_backend.md (example:
// launch_cfg/calibration/example_stereo.yaml):
//
//   left:  {image_width: 640, image_height: 480, K: [9 numbers], D: [4|5|8|12|14 numbers]}
//   right: {image_width: 640, image_height: 480, K: [...], D: [...]}
//   R: [9 numbers]   # row-major rotation, X_right = R * X_left + T (OpenCV's convention)
//   T: [3 numbers]   # metres; for a right camera 0.26 m to the right: [-0.26, 0, 0]
//
// Plain values, no OpenCV types. Validation is done once, here: every problem names the
// file, the line and the key (`left.K`, `T`) and what is allowed.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace scancrew::hardware_backend {

struct CameraCalibration {
  uint32_t width = 0, height = 0;  // image size the calibration was made at, px
  std::array<double, 9> K{};       // row-major camera matrix [fx 0 cx; 0 fy cy; 0 0 1], px
  std::vector<double> D;           // OpenCV distortion k1 k2 p1 p2 [k3 [k4 k5 k6 [s1..s4 [tx ty]]]]
};

struct StereoCalibration {
  std::string source;  // the file it was read from
  CameraCalibration left, right;
  std::array<double, 9> R_right_left{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  std::array<double, 3> T_right_left_m{};                         // m

  double baseline_m() const;  // |T|
};

using CalibrationErrors = std::vector<std::string>;

// Reads and validates a calibration file.
Result<StereoCalibration, CalibrationErrors> load_stereo_calibration(const std::string& path);
// The same from text; `label` names the source in messages (tests).
Result<StereoCalibration, CalibrationErrors> parse_stereo_calibration(const std::string& text,
                                                                      const std::string& label);

}  // namespace scancrew::hardware_backend
