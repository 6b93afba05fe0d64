#pragma once

// HardwareBackend: the `hardware` backend, one instance per robot (per_robot: true). It
// publishes, in the robot's namespace, the topics the sim backend publishes for a robot:
//   stereo  (StereoFrame: rectified 8-bit gray pair, rectified left intrinsics, |T|;
//            stamp = time on the component's clock when both grabs returned)
//   imu     (Imu: one per valid line of the serial IMU; stamp = time of the poll that read it)
// and forwards each cmd_vel (VelocityCommand) to the robot base as one UDP datagram.
// Devices: StereoRig (OpenCV VideoCapture + rectification), SerialPort + ImuLineReader
// (line protocol in imu_line_reader.hpp), BaseCommandLink (datagram layout in
// base_command_link.hpp). Parameters and formats: docs/hardware_backend.md.
//
// configure() loads the calibration and opens every device before it creates any endpoint;
// the first failure names the parameter, the device and the cause, and everything opened
// so far is closed again. At run time nothing is fatal: dropped frames (by reason), IMU
// lines that do not parse, read and send errors are counted, logged the first time, and
// summed up at shutdown.
//
// Not covered: hardware time synchronisation (stamps are host times at reception) and
// camera triggering (the two cameras free-run; grab() takes them back to back).
//
// Thread safety: the callbacks run in the component's one mutually exclusive group (they
// share the counters; do not give it a reentrant callback_group). The camera timer blocks
// in grab() for up to a frame period on V4L2, and the IMU poll waits meanwhile; a
// multi-threaded executor keeps other components going. stats() is for when the component
// is not active (after Launch::run()).

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "components/hardware_backend/base_command_link.hpp"
#include "components/hardware_backend/imu_line_reader.hpp"
#include "components/hardware_backend/serial_port.hpp"
#include "components/hardware_backend/stereo_rig.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::hardware_backend {

class HardwareBackend final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "real robot: stereo cameras (OpenCV/V4L2, rectified), serial IMU, cmd_vel to the base over "
      "UDP (the hardware backend)";
  struct Config {
    // stereo cameras
    std::string left_device, right_device;    // /dev/videoN, or anything VideoCapture opens
    CameraApi camera_api = CameraApi::kAuto;  // auto | v4l2 | images | any
    std::string calibration;                  // calibration file, relative to the working dir
    double rate_hz = 15.0;                    // frames grabbed per second
    uint32_t width = 0, height = 0;           // requested capture size, px; 0 = calibration's
    double rectify_alpha = 0.0;               // 0: valid pixels only .. 1: all source pixels
    uint32_t camera_buffer_frames = 1;        // V4L2 driver queue (1 = the freshest frame)
    // where the left camera sits on the body (x forward, y left, z up from the floor under
    // the robot's centre); the rectified rig looks level along body +x
    std::vector<double> camera_mount_m = {0.25, 0.0, 0.35};
    // serial IMU
    std::string imu_device;  // e.g. /dev/ttyUSB0; "" = no IMU (the imu topic stays silent)
    uint32_t imu_baud = 115200;
    double imu_poll_hz = 400.0;         // reads per second; >= the IMU's line rate
    uint32_t imu_max_line_bytes = 256;  // longer lines are discarded
    double imu_silence_s = 1.0;         // warn when no valid line arrives for this long
    // robot base
    std::string base_host;   // IPv4 of the base controller; "" = cmd_vel is read and dropped
    uint32_t base_port = 0;  // UDP port, required with base_host
  };
  static Config read_config(ParamReader& p);

  struct Stats {
    uint64_t frames_published = 0;
    std::array<uint64_t, kFrameStatusCount> frames_dropped{};  // by FrameStatus
    uint64_t frames_no_buffer = 0;  // grabbed but no free slot in the stereo pool
    ImuLineStats imu_lines;
    uint64_t imu_published = 0, imu_no_buffer = 0, imu_read_errors = 0, imu_silences = 0;
    uint64_t commands_sent = 0, command_send_errors = 0, commands_without_base = 0;
    uint64_t commands_not_finite = 0;  // a NaN or infinite speed: a stop was sent instead
    uint64_t stop_commands_sent = 0;   // the zero command sent on deactivate
  };

  HardwareBackend(ComponentContext context, Config config);
  ~HardwareBackend() override;

  Stats stats() const;
  const StereoRig* stereo_rig() const { return rig_.get(); }

 private:
  Result<void, std::string> on_configure() override;
  void on_activate() override;
  void on_deactivate() override;
  void on_shutdown() override;
  void capture();
  void drop_frame(FrameStatus status);
  void poll_imu();
  void publish_imu(const ImuReading& reading, int64_t stamp_ns);
  void forward(const msg::VelocityCommand& command);
  std::string base_name() const;

  Config config_;
  std::unique_ptr<StereoRig> rig_;
  SerialPort imu_port_;
  ImuLineReader imu_reader_;
  std::array<char, 4096> imu_buffer_{};  // one read(); refilled until the port is drained
  BaseCommandLink base_;
  Publisher<msg::StereoFrame> stereo_;
  Publisher<msg::Imu> imu_;
  Stats stats_;
  std::array<bool, kFrameStatusCount> drop_logged_{};
  bool imu_read_error_logged_ = false, send_error_logged_ = false, no_buffer_logged_ = false;
  bool imu_silent_ = false;
  int64_t last_imu_ns_ = 0;
};

}  // namespace scancrew::hardware_backend
