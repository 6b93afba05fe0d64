#pragma once

// StereoRig: two cameras read through OpenCV's VideoCapture (V4L2 on the robots; an
// image sequence "dir/left_%03d.png" in the tests) and rectified with a StereoCalibration.
// Rectification (cv::stereoRectify, zero disparity at infinity) and the remap tables
// (cv::initUndistortRectifyMap) are computed once, in open(); each frame is grabbed,
// converted to 8-bit gray and remapped straight into the caller's message buffers.
//
// Opening fails with a message naming the parameter, the device and the cause
// ("left_device '/dev/video7': cannot open (no such device)"); a camera that delivers
// another image size than the calibration's is refused. Per frame, failures are a
// FrameStatus: the caller counts them and keeps running.
//
// OpenCV may print its own warning at each failed grab (OPENCV_LOG_LEVEL=ERROR silences
// it); its log level is process-wide and shared with other components, so it is left alone.
//
// Thread safety: one thread at a time. Allocation: grab() and rectify_into() reuse their
// buffers (the message vectors keep their capacity); OpenCV's decoders and remap may use
// small scratch buffers of their own. OpenCV stays inside stereo_rig.cpp (pimpl).

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "components/hardware_backend/stereo_calibration.hpp"
#include "core/enum_names.hpp"
#include "core/result.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::hardware_backend {

// How VideoCapture opens the devices: auto (V4L2 for /dev/*, the image-sequence reader
// for a name with a %d pattern, else any backend), v4l2, images, any.
enum class CameraApi : uint8_t { kAuto, kV4l2, kImages, kAny };

inline constexpr EnumNames<CameraApi, 4> kCameraApiNames = {{{CameraApi::kAuto, "auto"},
                                                             {CameraApi::kV4l2, "v4l2"},
                                                             {CameraApi::kImages, "images"},
                                                             {CameraApi::kAny, "any"}}};

struct StereoRigConfig {
  std::string left_device, right_device;  // /dev/videoN, an image-sequence pattern, a URL...
  CameraApi api = CameraApi::kAuto;       // how VideoCapture opens the devices (above)
  double rate_hz = 15.0;                  // asked of V4L2 cameras (CAP_PROP_FPS)
  double rectify_alpha = 0.0;  // cv::stereoRectify alpha: 0 crops to valid pixels, 1 keeps all
  uint32_t driver_buffer_frames = 1;  // V4L2 frames queued in the driver (latency vs. drops)
};

enum class FrameStatus : uint8_t {
  kOk,
  kGrabFailed,               // a camera delivered no frame (unplugged, end of a sequence)
  kSizeMismatch,             // left and right images differ in size
  kCalibrationSizeMismatch,  // both the same size, but not the calibrated one
  kUnsupportedFormat,        // not 8-bit gray/BGR/BGRA
};
inline constexpr size_t kFrameStatusCount = 5;
std::string_view to_string(FrameStatus status);

class StereoRig {
 public:
  static Result<std::unique_ptr<StereoRig>, std::string> open(const StereoRigConfig& config,
                                                              const StereoCalibration& calibration);
  ~StereoRig();
  StereoRig(const StereoRig&) = delete;
  StereoRig& operator=(const StereoRig&) = delete;

  // The rectified left camera (the right one shares it after rectification), and |T|.
  const msg::CameraIntrinsics& intrinsics() const;
  double baseline_m() const;

  // Grabs a frame from both cameras, back to back (the decode is left to rectify_into(),
  // so the two exposures are as close as the drivers allow).
  FrameStatus grab();
  // Decodes the grabbed pair, converts to gray and rectifies it into frame.left/right
  // (resized to width*height), and sets frame.intrinsics and frame.baseline_m.
  FrameStatus rectify_into(msg::StereoFrame& frame);

 private:
  struct Impl;
  explicit StereoRig(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::hardware_backend
