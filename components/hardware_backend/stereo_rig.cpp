#include "components/hardware_backend/stereo_rig.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <system_error>

#include "components/hardware_backend/device_error.hpp"

namespace scancrew::hardware_backend {

std::string_view to_string(FrameStatus status) {
  switch (status) {
    case FrameStatus::kOk:
      return "ok";
    case FrameStatus::kGrabFailed:
      return "grab failed";
    case FrameStatus::kSizeMismatch:
      return "left/right size mismatch";
    case FrameStatus::kCalibrationSizeMismatch:
      return "image size differs from the calibration";
    case FrameStatus::kUnsupportedFormat:
      return "unsupported pixel format";
  }
  return "?";
}

namespace {

// The API to open `device` with: `api` itself, or for kAuto the device's kind (a /dev/ path is
// V4L2, a printf pattern an image sequence, anything else OpenCV's choice). Never kAuto.
CameraApi pick_api(CameraApi api, const std::string& device) {
  if (api != CameraApi::kAuto) return api;
  if (device.starts_with("/dev/")) return CameraApi::kV4l2;
  if (device.find('%') != std::string::npos) return CameraApi::kImages;
  return CameraApi::kAny;
}

int opencv_api(CameraApi api) {
  switch (api) {
    case CameraApi::kV4l2:
      return cv::CAP_V4L2;
    case CameraApi::kImages:
      return cv::CAP_IMAGES;
    case CameraApi::kAny:
    case CameraApi::kAuto:
      break;
  }
  return cv::CAP_ANY;
}

// The file of an image-sequence pattern ("left_%03d.png") for one index, or nothing when
// the pattern is not one printf-style %d (optionally zero-padded to a width).
std::optional<std::string> sequence_file(const std::string& pattern, int index) {
  const size_t percent = pattern.find('%');
  if (percent == std::string::npos || pattern.find('%', percent + 1) != std::string::npos)
    return std::nullopt;
  size_t i = percent + 1;
  const bool zero_pad = i < pattern.size() && pattern[i] == '0';
  int width = 0;
  while (i < pattern.size() && pattern[i] >= '0' && pattern[i] <= '9')
    width = width * 10 + (pattern[i++] - '0');
  if (i >= pattern.size() || pattern[i] != 'd' || width > 16) return std::nullopt;
  std::string number = std::to_string(index);
  if (static_cast<int>(number.size()) < width)
    number.insert(0, static_cast<size_t>(width) - number.size(), zero_pad ? '0' : ' ');
  return pattern.substr(0, percent) + number + pattern.substr(i + 1);
}

// Why `device` cannot be opened with `api`, found without OpenCV (whose own messages go to
// stderr and name no cause); empty when nothing is wrong that we can see.
std::string precheck(const std::string& device, CameraApi api) {
  if (device.empty()) return "no device given";
  if (api == CameraApi::kV4l2) {
    const int fd = ::open(device.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return device_open_error(errno, "video");
    ::close(fd);
    return {};
  }
  if (api == CameraApi::kImages) {
    const auto first = sequence_file(device, 0);
    if (!first) return "not an image-sequence pattern; allowed: one %d, e.g. 'dir/left_%03d.png'";
    std::error_code ec;
    // the sequence may start at 0 or 1 (OpenCV's rule)
    if (!std::filesystem::exists(*first, ec) &&
        !std::filesystem::exists(*sequence_file(device, 1), ec))
      return "no image matches the pattern ('" + *first + "' does not exist)";
  }
  return {};
}

std::string size_text(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height) + " px";
}

template <size_t N>
cv::Mat matrix(const std::array<double, N>& values, int rows, int cols) {
  cv::Mat m(rows, cols, CV_64F);
  std::copy(values.begin(), values.end(), m.ptr<double>());
  return m;
}

cv::Mat distortion(const std::vector<double>& d) {
  if (d.empty()) return {};
  return cv::Mat(d, /*copyData=*/true);
}

}  // namespace

struct StereoRig::Impl {
  cv::VideoCapture left, right;
  std::string left_name, right_name;  // "left_device '/dev/video0'", for messages
  cv::Size size;
  cv::Mat left_map1, left_map2, right_map1, right_map2;
  cv::Mat left_raw, right_raw, left_gray, right_gray;
  msg::CameraIntrinsics intrinsics;
  double baseline_m = 0;

  static Result<cv::VideoCapture, std::string> open_camera(const std::string& name,
                                                           const std::string& device,
                                                           const StereoRigConfig& config,
                                                           const StereoCalibration& calibration,
                                                           cv::Size size) {
    const CameraApi api = pick_api(config.api, device);
    if (std::string cause = precheck(device, api); !cause.empty())
      return make_unexpected(name + ": cannot open (" + cause + ")");
    cv::VideoCapture cap;
    bool opened = false;
    try {
      opened = cap.open(device, opencv_api(api));
      if (opened && api == CameraApi::kV4l2) {
        cap.set(cv::CAP_PROP_FRAME_WIDTH, size.width);
        cap.set(cv::CAP_PROP_FRAME_HEIGHT, size.height);
        cap.set(cv::CAP_PROP_FPS, config.rate_hz);
        cap.set(cv::CAP_PROP_BUFFERSIZE, config.driver_buffer_frames);
      }
    } catch (const cv::Exception& e) {
      return make_unexpected(name + ": cannot open (OpenCV: " + e.what() + ")");
    }
    if (!opened)
      return make_unexpected(
          name + ": cannot open (no OpenCV video backend accepts it" +
          (api == CameraApi::kV4l2 ? std::string("; not a V4L2 capture device?") : std::string()) +
          ")");
    const int width = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_WIDTH));
    const int height = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_HEIGHT));
    // 0 = the backend cannot tell before the first frame: rectify_into() checks each frame
    if (width > 0 && height > 0 && cv::Size(width, height) != size)
      return make_unexpected(name + ": delivers " + size_text(width, height) +
                             ", but the calibration '" + calibration.source + "' is for " +
                             size_text(size.width, size.height));
    return cap;
  }

  Result<void, std::string> rectify(const StereoRigConfig& config, const StereoCalibration& c) {
    try {
      const cv::Mat k1 = matrix(c.left.K, 3, 3), k2 = matrix(c.right.K, 3, 3);
      const cv::Mat d1 = distortion(c.left.D), d2 = distortion(c.right.D);
      const cv::Mat r = matrix(c.R_right_left, 3, 3), t = matrix(c.T_right_left_m, 3, 1);
      cv::Mat r1, r2, p1, p2, q;
      cv::stereoRectify(k1, d1, k2, d2, size, r, t, r1, r2, p1, p2, q, cv::CALIB_ZERO_DISPARITY,
                        config.rectify_alpha, size);
      cv::initUndistortRectifyMap(k1, d1, r1, p1, size, CV_16SC2, left_map1, left_map2);
      cv::initUndistortRectifyMap(k2, d2, r2, p2, size, CV_16SC2, right_map1, right_map2);
      intrinsics.width = static_cast<uint32_t>(size.width);
      intrinsics.height = static_cast<uint32_t>(size.height);
      intrinsics.fx = p1.at<double>(0, 0);
      intrinsics.fy = p1.at<double>(1, 1);
      intrinsics.cx = p1.at<double>(0, 2);
      intrinsics.cy = p1.at<double>(1, 2);
    } catch (const cv::Exception& e) {
      return make_unexpected("calibration '" + c.source +
                             "': rectification failed (OpenCV: " + e.what() + ")");
    }
    if (!(std::isfinite(intrinsics.fx) && intrinsics.fx > 0 && std::isfinite(intrinsics.fy) &&
          intrinsics.fy > 0))
      return make_unexpected("calibration '" + c.source +
                             "': rectification gives no usable focal length (fx " +
                             std::to_string(intrinsics.fx) + " px); check K, D and rectify_alpha");
    baseline_m = c.baseline_m();
    return {};
  }

  // The 8-bit gray view of a decoded frame (converted into `gray` when it has colour), or
  // nothing for a format we do not take.
  static const cv::Mat* to_gray(const cv::Mat& raw, cv::Mat& gray) {
    if (raw.depth() != CV_8U) return nullptr;
    switch (raw.channels()) {
      case 1:
        return &raw;
      case 3:
        cv::cvtColor(raw, gray, cv::COLOR_BGR2GRAY);
        return &gray;
      case 4:
        cv::cvtColor(raw, gray, cv::COLOR_BGRA2GRAY);
        return &gray;
      default:
        return nullptr;
    }
  }

  void remap_into(const cv::Mat& gray, const cv::Mat& map1, const cv::Mat& map2,
                  std::vector<uint8_t>& out) const {
    out.resize(static_cast<size_t>(size.width) * static_cast<size_t>(size.height));
    cv::Mat dst(size, CV_8UC1, out.data());  // a view of the message buffer: no copy
    cv::remap(gray, dst, map1, map2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
};

StereoRig::StereoRig(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
StereoRig::~StereoRig() = default;

Result<std::unique_ptr<StereoRig>, std::string> StereoRig::open(
    const StereoRigConfig& config, const StereoCalibration& calibration) {
  auto impl = std::make_unique<Impl>();
  impl->size =
      cv::Size(static_cast<int>(calibration.left.width), static_cast<int>(calibration.left.height));
  if (auto r = impl->rectify(config, calibration); !r) return make_unexpected(r.error());
  impl->left_name = "left_device '" + config.left_device + "'";
  impl->right_name = "right_device '" + config.right_device + "'";
  auto left =
      Impl::open_camera(impl->left_name, config.left_device, config, calibration, impl->size);
  if (!left) return make_unexpected(left.error());
  impl->left = std::move(left).value();
  // on failure the left camera is released with impl: nothing stays half-open
  auto right =
      Impl::open_camera(impl->right_name, config.right_device, config, calibration, impl->size);
  if (!right) return make_unexpected(right.error());
  impl->right = std::move(right).value();
  return std::unique_ptr<StereoRig>(new StereoRig(std::move(impl)));
}

const msg::CameraIntrinsics& StereoRig::intrinsics() const {
  return impl_->intrinsics;
}
double StereoRig::baseline_m() const {
  return impl_->baseline_m;
}

FrameStatus StereoRig::grab() {
  const bool left = impl_->left.grab();
  const bool right = impl_->right.grab();
  return left && right ? FrameStatus::kOk : FrameStatus::kGrabFailed;
}

FrameStatus StereoRig::rectify_into(msg::StereoFrame& frame) {
  Impl& m = *impl_;
  if (!m.left.retrieve(m.left_raw) || !m.right.retrieve(m.right_raw) || m.left_raw.empty() ||
      m.right_raw.empty())
    return FrameStatus::kGrabFailed;
  if (m.left_raw.size() != m.right_raw.size()) return FrameStatus::kSizeMismatch;
  if (m.left_raw.size() != m.size) return FrameStatus::kCalibrationSizeMismatch;
  const cv::Mat* left = Impl::to_gray(m.left_raw, m.left_gray);
  const cv::Mat* right = Impl::to_gray(m.right_raw, m.right_gray);
  if (left == nullptr || right == nullptr) return FrameStatus::kUnsupportedFormat;
  m.remap_into(*left, m.left_map1, m.left_map2, frame.left);
  m.remap_into(*right, m.right_map1, m.right_map2, frame.right);
  frame.intrinsics = m.intrinsics;
  frame.baseline_m = m.baseline_m;
  return FrameStatus::kOk;
}

}  // namespace scancrew::hardware_backend
