#include "components/hardware_backend/hardware_backend.hpp"

#include <chrono>
#include <cmath>

#include "components/hardware_backend/stereo_calibration.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"

namespace scancrew::hardware_backend {

namespace {

std::chrono::nanoseconds period(double rate_hz) {
  return std::chrono::nanoseconds(static_cast<int64_t>(std::llround(1e9 / rate_hz)));
}

std::string join(const std::vector<std::string>& parts, const char* separator) {
  std::string all;
  for (const auto& p : parts) all += (all.empty() ? "" : separator) + p;
  return all;
}

}  // namespace

HardwareBackend::Config HardwareBackend::read_config(ParamReader& p) {
  Config c;
  p.required("left_device", c.left_device)
      .doc(
          "left camera: /dev/videoN, an image-sequence pattern (dir/left_%03d.png), or anything "
          "cv::VideoCapture opens");
  p.required("right_device", c.right_device).doc("right camera, as left_device");
  p.choice("camera_api", c.camera_api, kCameraApiNames)
      .doc("auto: V4L2 for /dev/*, the image-sequence reader for a name with %d, else any backend");
  p.required("calibration", c.calibration)
      .doc("calibration file, relative to the launch file (--set: the working directory)");
  p.optional("rate_hz", c.rate_hz, {0.1, 1000})
      .doc("frames grabbed per second (also asked of V4L2 cameras)");
  p.optional("width", c.width, {0, 65535})
      .doc("requested capture width (px; both or neither; 0: the calibration's)");
  p.optional("height", c.height, {0, 65535})
      .doc("requested capture height (px; 0: the calibration's)");
  if ((c.width == 0) != (c.height == 0))
    p.report(c.width == 0 ? "width" : "height",
             "set width and height together, or neither (the calibration's image size)");
  p.optional("rectify_alpha", c.rectify_alpha, {-1, 1})
      .doc(
          "cv::stereoRectify alpha: 0 valid pixels only, 1 every source pixel, -1 OpenCV's "
          "default");
  p.optional("camera_buffer_frames", c.camera_buffer_frames, {1, 32})
      .doc("V4L2 driver queue (1: always the freshest frame)");
  p.optional_list("camera_mount_m", c.camera_mount_m, 3, {-10, 10})
      .doc(
          "the left camera on the body: x forward, y left, z up from the floor under the robot's "
          "centre (m)");
  p.optional("imu_device", c.imu_device)
      .doc("serial IMU device, e.g. /dev/ttyUSB0 (\"\": no IMU; the imu topic stays silent)");
  p.optional("imu_baud", c.imu_baud, {1200, 4000000}).doc("IMU baud rate (a termios rate)");
  if (!SerialPort::supported_baud(c.imu_baud))
    p.report("imu_baud", std::to_string(c.imu_baud) + " is not a termios baud rate; allowed: " +
                             SerialPort::supported_bauds());
  p.optional("imu_poll_hz", c.imu_poll_hz, {1, 10000})
      .doc("how often the port is read; at least the IMU's line rate (Hz)");
  p.optional("imu_max_line_bytes", c.imu_max_line_bytes, {32, 65536})
      .doc("longer IMU lines are discarded");
  p.optional("imu_silence_s", c.imu_silence_s, {0.001, 3600})
      .doc("warn once when no valid IMU line arrives for this long (s)");
  p.optional("base_host", c.base_host)
      .doc("base controller's IPv4 (\"\": cmd_vel is read and dropped, counted)");
  p.optional("base_port", c.base_port, {0, 65535})
      .doc("base controller's UDP port; required with base_host");
  if (!c.base_host.empty() && !BaseCommandLink::valid_ipv4(c.base_host))
    p.report("base_host", "'" + c.base_host +
                              "' is not an IPv4 address; allowed: a dotted quad such as "
                              "192.168.1.20, or '' (no base: cmd_vel is dropped)");
  if (!c.base_host.empty() && c.base_port == 0)
    p.report("base_port", "missing; required with base_host; allowed: a UDP port in [1, 65535]");
  return c;
}

HardwareBackend::HardwareBackend(ComponentContext context, Config config)
    : Component(std::move(context)),
      config_(std::move(config)),
      imu_reader_(config_.imu_max_line_bytes) {}

HardwareBackend::~HardwareBackend() = default;

std::string HardwareBackend::base_name() const {
  return "base_host '" + config_.base_host + ":" + std::to_string(config_.base_port) + "'";
}

Result<void, std::string> HardwareBackend::on_configure() {
  // every device is opened into a local first: an error returns with nothing left open
  config_.calibration = input_path("calibration", config_.calibration);
  auto calibration = load_stereo_calibration(config_.calibration);
  if (!calibration) return make_unexpected("calibration: " + join(calibration.error(), "; "));
  const CameraCalibration& cal = calibration->left;
  if (config_.width != 0 && (config_.width != cal.width || config_.height != cal.height))
    return make_unexpected("width x height " + std::to_string(config_.width) + "x" +
                           std::to_string(config_.height) + " px differs from the image size " +
                           std::to_string(cal.width) + "x" + std::to_string(cal.height) +
                           " px of the calibration '" + config_.calibration +
                           "'; allowed: 0 x 0 (the calibration's) or the calibrated size");
  StereoRigConfig rig_config;
  rig_config.left_device = config_.left_device;
  rig_config.right_device = config_.right_device;
  rig_config.api = config_.camera_api;
  rig_config.rate_hz = config_.rate_hz;
  rig_config.rectify_alpha = config_.rectify_alpha;
  rig_config.driver_buffer_frames = config_.camera_buffer_frames;
  auto rig = StereoRig::open(rig_config, *calibration);
  if (!rig) return make_unexpected(rig.error());

  SerialPort imu_port;
  if (!config_.imu_device.empty()) {
    auto port = SerialPort::open(config_.imu_device, config_.imu_baud);
    if (!port)
      return make_unexpected("imu_device '" + config_.imu_device + "': cannot open (" +
                             port.error() + ")");
    imu_port = std::move(port).value();
  }
  BaseCommandLink base;
  if (!config_.base_host.empty()) {
    auto link = BaseCommandLink::open(config_.base_host, static_cast<uint16_t>(config_.base_port));
    if (!link) return make_unexpected(base_name() + ": cannot open (" + link.error() + ")");
    base = std::move(link).value();
  }

  rig_ = std::move(rig).value();
  imu_port_ = std::move(imu_port);
  base_ = std::move(base);
  stereo_ = create_publisher<msg::StereoFrame>("stereo", {.pool_size = 4});
  imu_ = create_publisher<msg::Imu>("imu", {.pool_size = 16});
  create_subscription<msg::VelocityCommand>(
      "cmd_vel", {.depth = 1}, [this](Sample<msg::VelocityCommand>&& c) { forward(*c); });
  create_timer(period(config_.rate_hz), [this] { capture(); });
  if (imu_port_.is_open()) create_timer(period(config_.imu_poll_hz), [this] { poll_imu(); });

  const msg::CameraIntrinsics& k = rig_->intrinsics();
  SCANCREW_LOG_INFO(
      "%s: cameras '%s' / '%s' at %.1f Hz, rectified %ux%u px, fx %.1f px, baseline %.3f m; "
      "IMU %s; base %s",
      qualified_name().c_str(), config_.left_device.c_str(), config_.right_device.c_str(),
      config_.rate_hz, k.width, k.height, k.fx, rig_->baseline_m(),
      config_.imu_device.empty() ? "none" : config_.imu_device.c_str(),
      config_.base_host.empty() ? "none (cmd_vel dropped)" : base_name().c_str());
  return {};
}

void HardwareBackend::on_activate() {
  last_imu_ns_ = clock().now_ns();
  imu_silent_ = false;
}

void HardwareBackend::capture() {
  const FrameStatus grabbed = rig_->grab();
  const int64_t stamp_ns = clock().now_ns();  // capture time: no hardware sync (see header)
  if (grabbed != FrameStatus::kOk) {
    drop_frame(grabbed);
    return;
  }
  auto loan = stereo_.loan();
  if (!loan) {
    ++stats_.frames_no_buffer;  // the grabbed frame is dropped; the cameras stay in step
    if (!no_buffer_logged_)
      SCANCREW_LOG_WARN(
          "%s: stereo frame dropped: no free buffer (readers hold them all); "
          "further drops are counted",
          qualified_name().c_str());
    no_buffer_logged_ = true;
    return;
  }
  const FrameStatus rectified = rig_->rectify_into(**loan);
  if (rectified != FrameStatus::kOk) {
    drop_frame(rectified);  // the loan goes back to the pool
    return;
  }
  (*loan)->header.stamp_ns = stamp_ns;
  // optical frame (z forward, x right, y down) looking along body +x: x_cam = -y_body,
  // y_cam = -z_body, z_cam = x_body
  (*loan)->T_body_cam = {
      {config_.camera_mount_m[0], config_.camera_mount_m[1], config_.camera_mount_m[2]},
      {0.5, -0.5, 0.5, -0.5}};
  if (stereo_.publish(std::move(*loan))) ++stats_.frames_published;
}

void HardwareBackend::drop_frame(FrameStatus status) {
  const auto i = static_cast<size_t>(status);
  ++stats_.frames_dropped[i];
  if (drop_logged_[i]) return;
  drop_logged_[i] = true;
  SCANCREW_LOG_WARN(
      "%s: stereo frame dropped: %s (left_device '%s', right_device '%s'); further drops "
      "for this reason are counted and reported at shutdown",
      qualified_name().c_str(), std::string(to_string(status)).c_str(), config_.left_device.c_str(),
      config_.right_device.c_str());
}

void HardwareBackend::poll_imu() {
  const int64_t now_ns = clock().now_ns();
  for (;;) {  // drain: a short read means the port is empty
    auto n = imu_port_.read_available(imu_buffer_);
    if (!n) {
      ++stats_.imu_read_errors;
      if (!imu_read_error_logged_)
        SCANCREW_LOG_ERROR(
            "%s: imu_device '%s': read failed (%s); retrying every poll, "
            "further failures are counted",
            qualified_name().c_str(), config_.imu_device.c_str(), n.error().c_str());
      imu_read_error_logged_ = true;
      break;
    }
    imu_reader_.feed(std::string_view(imu_buffer_.data(), *n),
                     [&](const ImuReading& r) { publish_imu(r, now_ns); });
    if (*n < imu_buffer_.size()) break;
  }
  const double silent_s = static_cast<double>(now_ns - last_imu_ns_) * 1e-9;
  if (!imu_silent_ && silent_s > config_.imu_silence_s) {
    imu_silent_ = true;
    ++stats_.imu_silences;
    SCANCREW_LOG_WARN("%s: imu_device '%s': no valid IMU line for %.2f s (%llu malformed so far)",
                      qualified_name().c_str(), config_.imu_device.c_str(), silent_s,
                      static_cast<unsigned long long>(imu_reader_.stats().malformed));
  }
}

void HardwareBackend::publish_imu(const ImuReading& reading, int64_t stamp_ns) {
  last_imu_ns_ = stamp_ns;
  if (imu_silent_)
    SCANCREW_LOG_INFO("%s: imu_device '%s': IMU lines again", qualified_name().c_str(),
                      config_.imu_device.c_str());
  imu_silent_ = false;
  auto loan = imu_.loan();
  if (!loan) {
    ++stats_.imu_no_buffer;
    return;
  }
  msg::Imu& m = **loan;
  m.header.stamp_ns = stamp_ns;
  m.linear_acceleration_mps2 = reading.linear_acceleration_mps2;
  m.angular_velocity_radps = reading.angular_velocity_radps;
  if (imu_.publish(std::move(*loan))) ++stats_.imu_published;
}

void HardwareBackend::forward(const msg::VelocityCommand& command) {
  if (!base_.is_open()) {
    ++stats_.commands_without_base;
    return;
  }
  // a non-finite command (a NaN pose upstream, a forged message) never reaches the motors:
  // the base gets a stop instead (dropping it would leave the last command running)
  const bool finite = std::isfinite(command.linear_mps.x) && std::isfinite(command.linear_mps.y) &&
                      std::isfinite(command.linear_mps.z) && std::isfinite(command.yaw_rate_radps);
  if (!finite && stats_.commands_not_finite++ == 0)
    SCANCREW_LOG_ERROR(
        "%s: a velocity command that is not finite was replaced by a stop; further ones are "
        "counted",
        qualified_name().c_str());
  auto sent = finite
                  ? base_.send(robot_id(), command.header.stamp_ns, command.linear_mps.x,
                               command.linear_mps.y, command.linear_mps.z, command.yaw_rate_radps)
                  : base_.send(robot_id(), command.header.stamp_ns, 0, 0, 0, 0);
  if (sent) {
    stats_.commands_sent += finite ? 1 : 0;
    return;
  }
  ++stats_.command_send_errors;
  if (!send_error_logged_)
    SCANCREW_LOG_ERROR("%s: %s: send failed (%s); further failures are counted",
                       qualified_name().c_str(), base_name().c_str(), sent.error().c_str());
  send_error_logged_ = true;
}

void HardwareBackend::on_deactivate() {
  // the graph stops driving: tell the base to stop rather than leave it on the last command
  if (!base_.is_open()) return;
  if (base_.send(robot_id(), clock().now_ns(), 0, 0, 0, 0)) ++stats_.stop_commands_sent;
}

HardwareBackend::Stats HardwareBackend::stats() const {
  Stats s = stats_;
  s.imu_lines = imu_reader_.stats();
  return s;
}

void HardwareBackend::on_shutdown() {
  if (!rig_) return;  // never configured
  const Stats s = stats();
  const auto dropped = [&s](FrameStatus f) {
    return static_cast<unsigned long long>(s.frames_dropped[static_cast<size_t>(f)]);
  };
  SCANCREW_LOG_INFO(
      "%s: %llu frames published; dropped: %llu grab failed, %llu left/right size mismatch, "
      "%llu calibration size mismatch, %llu unsupported format, %llu no buffer; IMU: %llu "
      "published, %llu malformed lines, %llu overlong, %llu read errors; base: %llu commands "
      "sent, %llu send errors, %llu without a base, %llu not finite (a stop sent instead)",
      qualified_name().c_str(), static_cast<unsigned long long>(s.frames_published),
      dropped(FrameStatus::kGrabFailed), dropped(FrameStatus::kSizeMismatch),
      dropped(FrameStatus::kCalibrationSizeMismatch), dropped(FrameStatus::kUnsupportedFormat),
      static_cast<unsigned long long>(s.frames_no_buffer),
      static_cast<unsigned long long>(s.imu_published),
      static_cast<unsigned long long>(s.imu_lines.malformed),
      static_cast<unsigned long long>(s.imu_lines.overlong),
      static_cast<unsigned long long>(s.imu_read_errors),
      static_cast<unsigned long long>(s.commands_sent),
      static_cast<unsigned long long>(s.command_send_errors),
      static_cast<unsigned long long>(s.commands_without_base),
      static_cast<unsigned long long>(s.commands_not_finite));
}

SCANCREW_REGISTER_COMPONENT(HardwareBackend, "hardware_backend")

}  // namespace scancrew::hardware_backend
