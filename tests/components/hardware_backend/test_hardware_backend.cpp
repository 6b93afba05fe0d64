// The hardware backend against loopback fakes, on sim time with the step executor:
// cameras are image sequences written with cv::imwrite, the IMU is a pseudo-terminal whose
// master end the test writes, and the base is a UDP socket the test binds on 127.0.0.1.
// Every wait on the outside world is bounded (2 s).

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <pty.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "components/hardware_backend/base_command_link.hpp"
#include "components/hardware_backend/hardware_backend.hpp"
#include "components/hardware_backend/imu_line_reader.hpp"
#include "components/hardware_backend/stereo_calibration.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::hardware_backend {
namespace {

using hardware_backend::FrameStatus;
using namespace std::chrono_literals;

constexpr auto kWaitLimit = 2s;  // the longest any test waits for a device

// Records what the backend publishes.
class HwRecorder final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: records stereo and imu";
  struct Config {};
  static Config read_config(ParamReader&) { return {}; }
  HwRecorder(ComponentContext c, Config) : Component(std::move(c)) {}

  struct Frame {
    int64_t stamp_ns = 0;
    msg::CameraIntrinsics intrinsics;
    double baseline_m = 0;
    std::vector<uint8_t> left, right;
  };
  std::vector<Frame> frames;
  std::vector<msg::Imu> imu;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::StereoFrame>(
        "stereo", {.depth = 8}, [this](Sample<msg::StereoFrame>&& s) {
          frames.push_back({s->header.stamp_ns, s->intrinsics, s->baseline_m, s->left, s->right});
        });
    create_subscription<msg::Imu>("imu", {.depth = 64},
                                  [this](Sample<msg::Imu>&& s) { imu.push_back(*s); });
    return {};
  }
};
SCANCREW_REGISTER_COMPONENT(HwRecorder, "test_hw_recorder")

// A temporary directory, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "scancrew_hw_XXXXXX").string();
    const char* made = ::mkdtemp(pattern.data());
    EXPECT_NE(made, nullptr);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

struct Calibration {
  int width = 64, height = 48;
  double fx = 50, fy = 50;
  double cx = (64 - 1) / 2.0, cy = (48 - 1) / 2.0;  // the image centre: rectification keeps it
  std::vector<double> left_d = {0, 0, 0, 0, 0}, right_d = {0, 0, 0, 0, 0};
  std::vector<double> r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::vector<double> t = {-0.26, 0, 0};
  std::string left_k_override;  // replaces left.K's list when set (malformed files)
};

std::string list(const std::vector<double>& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
  s << "]";
  return s.str();
}

std::string calibration_yaml(const Calibration& c) {
  const std::vector<double> k = {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
  const std::string size =
      "image_width: " + std::to_string(c.width) + "\n  image_height: " + std::to_string(c.height);
  return "left:\n  " + size +
         "\n  K: " + (c.left_k_override.empty() ? list(k) : c.left_k_override) +
         "\n  D: " + list(c.left_d) + "\nright:\n  " + size + "\n  K: " + list(k) +
         "\n  D: " + list(c.right_d) + "\nR: " + list(c.r) + "\nT: " + list(c.t) + "\n";
}

// A random-dot scene seen by a rectified pair: right(x) = left(x + d) (disparity d).
struct StereoImages {
  cv::Mat left, right;
};
StereoImages make_pair(int width, int height, int disparity_px, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> dot(0, 255);
  cv::Mat wide(height, width + disparity_px, CV_8UC1);
  for (int y = 0; y < wide.rows; ++y)
    for (int x = 0; x < wide.cols; ++x) wide.at<uint8_t>(y, x) = static_cast<uint8_t>(dot(rng));
  return {wide(cv::Rect(0, 0, width, height)).clone(),
          wide(cv::Rect(disparity_px, 0, width, height)).clone()};
}

std::vector<uint8_t> bytes_of(const cv::Mat& m) {
  return std::vector<uint8_t>(m.datastart, m.dataend);
}

class HardwareBackendTest : public ::testing::Test {
 protected:
  static constexpr int kDisparityPx = 5;

  // left_%03d.png / right_%03d.png, frames 0..n-1; returns the pairs written.
  std::vector<StereoImages> write_sequence(int n, int width = 64, int height = 48) {
    std::vector<StereoImages> pairs;
    for (int i = 0; i < n; ++i) {
      pairs.push_back(make_pair(width, height, kDisparityPx, 100 + i));
      char name[32];
      std::snprintf(name, sizeof(name), "%03d.png", i);
      EXPECT_TRUE(cv::imwrite(dir_.file(std::string("left_") + name), pairs.back().left));
      EXPECT_TRUE(cv::imwrite(dir_.file(std::string("right_") + name), pairs.back().right));
    }
    return pairs;
  }

  std::string write_calibration(const Calibration& c) {
    std::string path = dir_.file("stereo.yaml");
    std::ofstream(path) << calibration_yaml(c);
    return path;
  }

  // The camera part of the parameters, for the sequence and calibration in the temp dir.
  std::string camera_params() const {
    return "left_device: '" + dir_.file("left_%03d.png") + "', right_device: '" +
           dir_.file("right_%03d.png") + "', calibration: '" + dir_.file("stereo.yaml") +
           "', rate_hz: 10";
  }

  static std::string launch_text(const std::string& params, double duration_s = 0.45) {
    return R"(
clock: sim
executor: {type: step}
run: {duration_s: )" +
           std::to_string(duration_s) + R"(, sim_step_s: 0.01}
robots:
  - {id: 7, namespace: r1}
components:
  - name: hardware
    type: hardware_backend
    params: {)" +
           params + R"(}
  - {name: recorder, type: test_hw_recorder}
)";
  }

  struct Run {
    std::unique_ptr<Launch> launch;
    HardwareBackend* backend = nullptr;
    HwRecorder* recorder = nullptr;
  };

  static Run compose(const std::string& params, double duration_s = 0.45) {
    auto launch = Launch::from_string(launch_text(params, duration_s), "hw.yaml");
    Run r;
    EXPECT_TRUE(launch) << (launch ? "" : errors_of(launch));
    if (!launch) return r;
    r.launch = std::move(launch).value();
    for (const auto& c : r.launch->components()) {
      if (auto* b = dynamic_cast<HardwareBackend*>(c.get())) r.backend = b;
      if (auto* rec = dynamic_cast<HwRecorder*>(c.get())) r.recorder = rec;
    }
    EXPECT_NE(r.backend, nullptr);
    EXPECT_NE(r.recorder, nullptr);
    return r;
  }

  template <class L>
  static std::string errors_of(const L& launch) {
    std::string all;
    for (const auto& e : launch.error()) all += e + "\n";
    return all;
  }

  // The launch's errors, for a composition that must fail.
  static std::string composition_error(const std::string& params) {
    auto launch = Launch::from_string(launch_text(params), "hw.yaml");
    EXPECT_FALSE(launch) << "composed although it should not";
    return launch ? std::string() : errors_of(launch);
  }

  TempDir dir_;
};

TEST_F(HardwareBackendTest, PublishesTheImageSequenceUnchangedUnderIdentityRectification) {
  const auto pairs = write_sequence(3);
  write_calibration({});
  Run run = compose(camera_params());
  ASSERT_TRUE(run.launch);
  run.launch->run();  // ticks at 0.1 .. 0.4 s: three frames, then the sequence has ended

  ASSERT_EQ(run.recorder->frames.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const HwRecorder::Frame& f = run.recorder->frames[i];
    EXPECT_EQ(f.stamp_ns, static_cast<int64_t>(i + 1) * 100'000'000);  // capture time, sim clock
    EXPECT_EQ(f.intrinsics.width, 64u);
    EXPECT_EQ(f.intrinsics.height, 48u);
    EXPECT_NEAR(f.intrinsics.fx, 50.0, 1e-6);
    EXPECT_NEAR(f.intrinsics.fy, 50.0, 1e-6);
    EXPECT_NEAR(f.intrinsics.cx, 31.5, 1e-6);
    EXPECT_NEAR(f.intrinsics.cy, 23.5, 1e-6);
    EXPECT_DOUBLE_EQ(f.baseline_m, 0.26);
    // identity rotation, no distortion: the rectified pair is the input pair
    EXPECT_EQ(f.left, bytes_of(pairs[i].left)) << "frame " << i;
    EXPECT_EQ(f.right, bytes_of(pairs[i].right)) << "frame " << i;
    // and still a rectified pair: each right row is its left row shifted by the disparity
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x + kDisparityPx < 64; ++x)
        ASSERT_EQ(f.right[y * 64 + x], f.left[y * 64 + x + kDisparityPx]) << y << "," << x;
  }
  const auto stats = run.backend->stats();
  EXPECT_EQ(stats.frames_published, 3u);
  EXPECT_EQ(stats.frames_dropped[static_cast<size_t>(FrameStatus::kGrabFailed)], 1u);
}

TEST_F(HardwareBackendTest, RectifiesWithTheCalibrationsDistortionAndRotationLikeOpenCv) {
  const auto pairs = write_sequence(1);
  Calibration c;
  c.left_d = {-0.08, 0.01, 0.001, -0.001, 0};
  c.right_d = {-0.06, 0.005, 0, 0, 0};
  const double a = 1.5 * M_PI / 180;  // the right camera yawed by 1.5 degrees
  c.r = {std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a)};
  c.t = {-0.2, 0.004, 0.002};
  write_calibration(c);
  Run run = compose(camera_params(), 0.15);
  ASSERT_TRUE(run.launch);
  run.launch->run();
  ASSERT_EQ(run.recorder->frames.size(), 1u);
  const HwRecorder::Frame& f = run.recorder->frames[0];

  // the reference: OpenCV called directly on the same calibration
  const cv::Mat k = (cv::Mat_<double>(3, 3) << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  const cv::Mat r = cv::Mat(c.r).reshape(1, 3), t = cv::Mat(c.t);
  cv::Mat r1, r2, p1, p2, q, lm1, lm2, rm1, rm2, left, right;
  const cv::Size size(64, 48);
  cv::stereoRectify(k, cv::Mat(c.left_d), k, cv::Mat(c.right_d), size, r, t, r1, r2, p1, p2, q,
                    cv::CALIB_ZERO_DISPARITY, 0.0, size);
  cv::initUndistortRectifyMap(k, cv::Mat(c.left_d), r1, p1, size, CV_16SC2, lm1, lm2);
  cv::initUndistortRectifyMap(k, cv::Mat(c.right_d), r2, p2, size, CV_16SC2, rm1, rm2);
  cv::remap(pairs[0].left, left, lm1, lm2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  cv::remap(pairs[0].right, right, rm1, rm2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);

  EXPECT_EQ(f.intrinsics.width, 64u);
  EXPECT_EQ(f.intrinsics.height, 48u);
  EXPECT_DOUBLE_EQ(f.intrinsics.fx, p1.at<double>(0, 0));
  EXPECT_DOUBLE_EQ(f.intrinsics.fy, p1.at<double>(1, 1));
  EXPECT_DOUBLE_EQ(f.intrinsics.cx, p1.at<double>(0, 2));
  EXPECT_DOUBLE_EQ(f.intrinsics.cy, p1.at<double>(1, 2));
  EXPECT_DOUBLE_EQ(f.baseline_m, std::sqrt(0.2 * 0.2 + 0.004 * 0.004 + 0.002 * 0.002));
  // rectified: the right camera's projection differs from the left by the baseline only
  EXPECT_NEAR(-p2.at<double>(0, 3) / p2.at<double>(0, 0), f.baseline_m, 1e-9);
  EXPECT_EQ(f.left, bytes_of(left));
  EXPECT_EQ(f.right, bytes_of(right));
  EXPECT_NE(f.left, bytes_of(pairs[0].left));  // the calibration did change the images
  EXPECT_NE(f.right, bytes_of(pairs[0].right));
}

TEST_F(HardwareBackendTest, DropsAFrameWhoseLeftAndRightSizesDifferAndKeepsRunning) {
  write_sequence(3);
  // frame 1 of the right camera comes in at another size
  const cv::Mat small = make_pair(32, 24, kDisparityPx, 9).right;
  ASSERT_TRUE(cv::imwrite(dir_.file("right_001.png"), small));
  write_calibration({});
  Run run = compose(camera_params(), 0.35);
  ASSERT_TRUE(run.launch);
  run.launch->run();
  ASSERT_EQ(run.recorder->frames.size(), 2u);
  EXPECT_EQ(run.recorder->frames[0].stamp_ns, 100'000'000);
  EXPECT_EQ(run.recorder->frames[1].stamp_ns, 300'000'000);
  const auto stats = run.backend->stats();
  EXPECT_EQ(stats.frames_dropped[static_cast<size_t>(FrameStatus::kSizeMismatch)], 1u);
  EXPECT_EQ(stats.frames_published, 2u);
}

TEST_F(HardwareBackendTest, RefusesCamerasWhoseImageSizeDiffersFromTheCalibration) {
  write_sequence(1, 80, 60);
  write_calibration({});  // 64x48
  const std::string error = composition_error(camera_params());
  EXPECT_NE(error.find("left_device '" + dir_.file("left_%03d.png") +
                       "': delivers 80x60 px, but the calibration '" + dir_.file("stereo.yaml") +
                       "' is for 64x48 px"),
            std::string::npos)
      << error;
  // and a requested size that is not the calibrated one
  write_sequence(1);
  const std::string requested = composition_error(camera_params() + ", width: 640, height: 480");
  EXPECT_NE(requested.find("width x height 640x480 px differs from the image size 64x48 px"),
            std::string::npos)
      << requested;
}

TEST_F(HardwareBackendTest, NamesAMissingCamera) {
  write_sequence(1);
  write_calibration({});
  const std::string missing_left =
      composition_error("left_device: /dev/video77, right_device: '" + dir_.file("right_%03d.png") +
                        "', calibration: '" + dir_.file("stereo.yaml") + "'");
  EXPECT_NE(missing_left.find("left_device '/dev/video77': cannot open (no such device)"),
            std::string::npos)
      << missing_left;
  const std::string missing_right = composition_error(
      "left_device: '" + dir_.file("left_%03d.png") + "', right_device: '" +
      dir_.file("nothing_%03d.png") + "', calibration: '" + dir_.file("stereo.yaml") + "'");
  EXPECT_NE(missing_right.find("right_device '" + dir_.file("nothing_%03d.png") +
                               "': cannot open (no image matches the pattern"),
            std::string::npos)
      << missing_right;
}

TEST_F(HardwareBackendTest, NamesAMissingImuDeviceAndOneThatIsNotASerialPort) {
  write_sequence(1);
  write_calibration({});
  const std::string missing = composition_error(camera_params() + ", imu_device: /dev/ttyNOPE7");
  EXPECT_NE(missing.find("imu_device '/dev/ttyNOPE7': cannot open (no such device)"),
            std::string::npos)
      << missing;
  const std::string not_a_tty =
      composition_error(camera_params() + ", imu_device: '" + dir_.file("stereo.yaml") + "'");
  EXPECT_NE(not_a_tty.find("imu_device '" + dir_.file("stereo.yaml") +
                           "': cannot open (not a serial port"),
            std::string::npos)
      << not_a_tty;
}

size_t open_descriptors() {
  return static_cast<size_t>(std::distance(std::filesystem::directory_iterator("/proc/self/fd"),
                                           std::filesystem::directory_iterator()));
}

TEST_F(HardwareBackendTest, ClosesWhatItOpenedWhenALaterDeviceFails) {
  write_sequence(1);
  write_calibration({});
  int master = -1, slave = -1;
  char slave_path[256] = {};
  ASSERT_EQ(::openpty(&master, &slave, slave_path, nullptr, nullptr), 0);
  const size_t before = open_descriptors();
  // cameras and IMU open; the base cannot (a broadcast address needs SO_BROADCAST)
  const std::string error = composition_error(camera_params() + ", imu_device: '" + slave_path +
                                              "', base_host: 255.255.255.255, base_port: 5800");
  EXPECT_NE(error.find("base_host '255.255.255.255:5800': cannot open ("), std::string::npos)
      << error;
  EXPECT_EQ(open_descriptors(), before);  // the IMU port was closed again
  ::close(slave);
  ::close(master);
}

TEST_F(HardwareBackendTest, NamesTheCalibrationProblem) {
  write_sequence(1);
  Calibration c;
  c.left_k_override = "[50, 0, 31.5, 0, 50, 23.5, 0, 0]";
  write_calibration(c);
  const std::string malformed = composition_error(camera_params());
  EXPECT_NE(malformed.find(dir_.file("stereo.yaml") + ":4: left.K: has 8 numbers; allowed: 9"),
            std::string::npos)
      << malformed;

  std::filesystem::remove(dir_.file("stereo.yaml"));
  const std::string missing = composition_error(camera_params());
  EXPECT_NE(missing.find("calibration: " + dir_.file("stereo.yaml") +
                         ": cannot read the calibration file (no such file)"),
            std::string::npos)
      << missing;

  c = {};
  c.t = {0, 0, 0};
  write_calibration(c);
  const std::string zero = composition_error(camera_params());
  EXPECT_NE(zero.find("T: zero baseline"), std::string::npos) << zero;
}

TEST_F(HardwareBackendTest, TurnsSerialImuLinesIntoImuMessages) {
  write_sequence(1);
  write_calibration({});
  int master = -1, slave = -1;
  char slave_path[256] = {};
  ASSERT_EQ(::openpty(&master, &slave, slave_path, nullptr, nullptr), 0);
  Run run = compose(camera_params() + ", imu_device: '" + slave_path +
                        "', imu_baud: 921600, imu_poll_hz: 100, imu_max_line_bytes: 64",
                    0.05);
  ASSERT_TRUE(run.launch);
  const auto write = [master](const std::string& text) {
    ASSERT_EQ(::write(master, text.data(), text.size()), static_cast<ssize_t>(text.size()));
  };
  // steps the graph until `n` samples are out or the wait limit passes
  const auto run_until_samples = [&run](size_t n) {
    const auto deadline = std::chrono::steady_clock::now() + kWaitLimit;
    while (run.recorder->imu.size() < n && std::chrono::steady_clock::now() < deadline) {
      run.launch->run();
      std::this_thread::sleep_for(1ms);
    }
  };

  write("IMU,0.1,-0.2,9.81,0.01,0.02,-0.03\nIMU,bad,line\nIMU,1,2,3,4,5,6\nIMU,1.5,2");
  run_until_samples(2);
  ASSERT_EQ(run.recorder->imu.size(), 2u);
  const msg::Imu& first = run.recorder->imu[0];
  EXPECT_EQ(first.linear_acceleration_mps2.x, 0.1);
  EXPECT_EQ(first.linear_acceleration_mps2.y, -0.2);
  EXPECT_EQ(first.linear_acceleration_mps2.z, 9.81);
  EXPECT_EQ(first.angular_velocity_radps.x, 0.01);
  EXPECT_EQ(first.angular_velocity_radps.y, 0.02);
  EXPECT_EQ(first.angular_velocity_radps.z, -0.03);
  EXPECT_EQ(first.header.robot_id, 7u);
  EXPECT_GT(first.header.stamp_ns, 0);
  EXPECT_EQ(first.header.stamp_ns % 10'000'000, 0);  // stamped by a poll on the sim clock
  EXPECT_EQ(run.recorder->imu[1].angular_velocity_radps.z, 6.0);
  EXPECT_EQ(run.backend->stats().imu_lines.malformed, 1u);

  // the split line completes; an overlong line is discarded; CRLF is accepted
  write(",3,4,5,6\n" + std::string(100, '7') + "\nIMU,+1e-3,0,0,0,0,-0\r\n");
  run_until_samples(4);
  ASSERT_EQ(run.recorder->imu.size(), 4u);
  EXPECT_EQ(run.recorder->imu[2].linear_acceleration_mps2.x, 1.5);
  EXPECT_EQ(run.recorder->imu[2].angular_velocity_radps.z, 6.0);
  EXPECT_EQ(run.recorder->imu[3].linear_acceleration_mps2.x, 1e-3);
  const auto stats = run.backend->stats();
  EXPECT_EQ(stats.imu_lines.samples, 4u);
  EXPECT_EQ(stats.imu_lines.malformed, 1u);
  EXPECT_EQ(stats.imu_lines.overlong, 1u);
  EXPECT_EQ(stats.imu_published, 4u);
  EXPECT_EQ(stats.imu_read_errors, 0u);
  ::close(slave);
  ::close(master);
}

// A UDP socket on 127.0.0.1, an ephemeral port, closed at the end.
class UdpReceiver {
 public:
  UdpReceiver() {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    EXPECT_GE(fd_, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = 0;
    EXPECT_EQ(::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)), 0);
    socklen_t len = sizeof(addr);
    EXPECT_EQ(::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len), 0);
    port_ = ntohs(addr.sin_port);
  }
  ~UdpReceiver() { ::close(fd_); }
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;
  uint16_t port() const { return port_; }

  // One datagram, or nothing within timeout.
  std::optional<std::vector<uint8_t>> receive(std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) != 1) return std::nullopt;
    std::vector<uint8_t> buffer(512);
    const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), 0);
    if (n < 0) return std::nullopt;
    buffer.resize(static_cast<size_t>(n));
    return buffer;
  }

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
};

TEST_F(HardwareBackendTest, SendsEachVelocityCommandAsOneDatagramAndAStopOnDeactivate) {
  write_sequence(1);
  write_calibration({});
  UdpReceiver base;
  Run run = compose(
      camera_params() + ", base_host: 127.0.0.1, base_port: " + std::to_string(base.port()), 0.05);
  ASSERT_TRUE(run.launch);
  auto topic = run.launch->graph().topic<msg::VelocityCommand>("/r1/cmd_vel", 4);
  ASSERT_TRUE(topic);
  Publisher<msg::VelocityCommand> cmd_vel(*topic, 0, &run.launch->graph().clock(), nullptr);
  const auto command = [&](double vx, double vy, double vz, double yaw_rate, int64_t stamp) {
    auto loan = cmd_vel.loan();
    ASSERT_TRUE(loan);
    (*loan)->linear_mps = {vx, vy, vz};
    (*loan)->yaw_rate_radps = yaw_rate;
    (*loan)->header.stamp_ns = stamp;
    ASSERT_TRUE(cmd_vel.publish(std::move(*loan)));
  };
  const auto next = [&base]() -> hardware_backend::VelocityDatagram {
    auto bytes = base.receive(std::chrono::duration_cast<std::chrono::milliseconds>(kWaitLimit));
    EXPECT_TRUE(bytes) << "no datagram";
    if (!bytes) return {};
    EXPECT_EQ(bytes->size(), hardware_backend::kVelocityDatagramBytes);
    auto d = hardware_backend::decode_velocity_datagram(*bytes);
    EXPECT_TRUE(d) << (d ? "" : hardware_backend::to_string(d.error()));
    return d ? *d : hardware_backend::VelocityDatagram{};
  };

  command(0.5, -0.25, 0.125, 0.3, 123'456'789);
  run.launch->run();  // delivers the command; deactivating at the end sends a stop
  command(-1.0, 0, 0, -0.7, 987'654'321);
  run.launch->run();

  const hardware_backend::VelocityDatagram d1 = next(), stop1 = next(), d2 = next(), stop2 = next();
  EXPECT_EQ(d1.robot_id, 7u);
  EXPECT_EQ(d1.seq, 1u);
  EXPECT_EQ(d1.stamp_ns, 123'456'789);
  EXPECT_EQ(d1.vx_mps, 0.5);
  EXPECT_EQ(d1.vy_mps, -0.25);
  EXPECT_EQ(d1.vz_mps, 0.125);
  EXPECT_EQ(d1.yaw_rate_radps, 0.3);
  EXPECT_EQ(stop1.seq, 2u);
  EXPECT_EQ(stop1.vx_mps, 0.0);
  EXPECT_EQ(stop1.yaw_rate_radps, 0.0);
  EXPECT_EQ(stop1.stamp_ns, 50'000'000);  // the sim clock at deactivation
  EXPECT_EQ(d2.seq, 3u);
  EXPECT_EQ(d2.stamp_ns, 987'654'321);
  EXPECT_EQ(d2.vx_mps, -1.0);
  EXPECT_EQ(d2.yaw_rate_radps, -0.7);
  EXPECT_EQ(stop2.seq, 4u);
  EXPECT_FALSE(base.receive(0ms)) << "one datagram per command";
  command(std::nan(""), 0.5, 0, 0, 555);  // never reaches the motors: a stop instead
  run.launch->run();
  const hardware_backend::VelocityDatagram instead = next(), stop3 = next();
  EXPECT_EQ(instead.seq, 5u);
  EXPECT_EQ(instead.stamp_ns, 555);
  EXPECT_EQ(instead.vx_mps, 0.0);
  EXPECT_EQ(instead.vy_mps, 0.0);
  EXPECT_EQ(stop3.seq, 6u);
  EXPECT_FALSE(base.receive(0ms)) << "one datagram per command";
  const auto stats = run.backend->stats();
  EXPECT_EQ(stats.commands_sent, 2u);
  EXPECT_EQ(stats.commands_not_finite, 1u);
  EXPECT_EQ(stats.stop_commands_sent, 3u);
  EXPECT_EQ(stats.command_send_errors, 0u);
}

TEST_F(HardwareBackendTest, RejectsBadParametersByKey) {
  write_sequence(1);
  write_calibration({});
  const std::string host = composition_error(camera_params() + ", base_host: robot.local");
  EXPECT_NE(host.find("params.base_host: 'robot.local' is not an IPv4 address"), std::string::npos)
      << host;
  const std::string port = composition_error(camera_params() + ", base_host: 10.0.0.2");
  EXPECT_NE(port.find("params.base_port: missing"), std::string::npos) << port;
  const std::string baud = composition_error(camera_params() + ", imu_baud: 12345");
  EXPECT_NE(baud.find("params.imu_baud: 12345 is not a termios baud rate"), std::string::npos)
      << baud;
  const std::string api = composition_error(camera_params() + ", camera_api: gphoto");
  EXPECT_NE(api.find("params.camera_api: 'gphoto' is not allowed"), std::string::npos) << api;
}

TEST(ImuLineReader, ParsesSplitLinesAndCountsMalformedAndOverlongOnes) {
  hardware_backend::ImuLineReader reader(40);
  std::vector<hardware_backend::ImuReading> out;
  const auto feed = [&](std::string_view bytes) {
    reader.feed(bytes, [&](const hardware_backend::ImuReading& r) { out.push_back(r); });
  };
  feed("IMU,1,2,3,4,5,6\nIMU,0.5,");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(reader.buffered_bytes(), 8u);
  feed("0,0,0,0,-2.5e1\n\n");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].linear_acceleration_mps2.x, 0.5);
  EXPECT_EQ(out[1].angular_velocity_radps.z, -25.0);
  for (const char* bad : {"IMU,1,2,3,4,5\n", "IMU,1,2,3,4,5,6,7\n", "IMU,1,2,3,4,5,nan\n",
                          "imu,1,2,3,4,5,6\n", "IMU, 1,2,3,4,5,6\n", "IMU,1,2,3,4,5,6 \n",
                          "IMU,1,,3,4,5,6\n", "IMU,+-1,2,3,4,5,6\n", "IMU,1,2,3,4,5,1e999\n"})
    feed(bad);
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(reader.stats().malformed, 9u);
  feed(std::string(100, 'x'));  // no newline: the buffer stays bounded
  EXPECT_LE(reader.buffered_bytes(), 40u);
  feed("still the same line\nIMU,9,9,9,9,9,9\n");
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(reader.stats().overlong, 1u);
  EXPECT_EQ(reader.stats().samples, 3u);
}

TEST(VelocityDatagram, HasTheDocumentedLittleEndianLayoutAndRejectsOthers) {
  hardware_backend::VelocityDatagram d;
  d.robot_id = 0x01020304;
  d.seq = 0xA0B0C0D0;
  d.stamp_ns = -2;
  d.vx_mps = 1.0;
  d.vy_mps = -0.5;
  d.vz_mps = 0.25;
  d.yaw_rate_radps = 3.0;
  const auto bytes = hardware_backend::encode_velocity_datagram(d);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "SCVC");
  EXPECT_EQ(bytes[4], 1);
  EXPECT_EQ(bytes[5] | bytes[6] | bytes[7], 0);
  EXPECT_EQ(bytes[8], 0x04);   // robot id, least significant byte first
  EXPECT_EQ(bytes[15], 0xA0);  // seq's most significant byte
  EXPECT_EQ(bytes[16], 0xFE);  // stamp -2
  EXPECT_EQ(bytes[23], 0xFF);
  EXPECT_EQ(bytes[31], 0x3F);  // 1.0 = 0x3FF0000000000000
  EXPECT_EQ(bytes[30], 0xF0);
  auto back = hardware_backend::decode_velocity_datagram(bytes);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->robot_id, d.robot_id);
  EXPECT_EQ(back->seq, d.seq);
  EXPECT_EQ(back->stamp_ns, d.stamp_ns);
  EXPECT_EQ(back->vx_mps, 1.0);
  EXPECT_EQ(back->vy_mps, -0.5);
  EXPECT_EQ(back->vz_mps, 0.25);
  EXPECT_EQ(back->yaw_rate_radps, 3.0);

  auto wrong = bytes;
  wrong[0] = 'X';
  EXPECT_EQ(hardware_backend::decode_velocity_datagram(wrong).error(),
            hardware_backend::DatagramError::kBadMagic);
  wrong = bytes;
  wrong[4] = 2;
  EXPECT_EQ(hardware_backend::decode_velocity_datagram(wrong).error(),
            hardware_backend::DatagramError::kUnsupportedVersion);
  EXPECT_EQ(hardware_backend::decode_velocity_datagram(std::span(bytes).first(40)).error(),
            hardware_backend::DatagramError::kWrongSize);
}

TEST(StereoCalibration, ReadsTheExampleFile) {
  auto c = hardware_backend::load_stereo_calibration(SCANCREW_SOURCE_DIR
                                                     "/launch_cfg/calibration/example_stereo.yaml");
  ASSERT_TRUE(c) << c.error().front();
  EXPECT_EQ(c->left.width, 640u);
  EXPECT_EQ(c->left.height, 480u);
  EXPECT_NEAR(c->left.K[0], 320.0, 5.0);
  EXPECT_NEAR(c->baseline_m(), 0.26, 1e-3);
}

TEST(StereoCalibration, ListsEveryProblemWithItsKey) {
  const std::string text = R"(left:
  image_width: 640
  image_height: 480
  K: [320, 0, 319.5, 0, 320, 239.5, 0, 0, 2]
  D: [0, 0, 0]
right:
  image_width: 640
  image_height: 480.5
  K: [320, 0, 319.5, 0, 320, 239.5, 0, 0, 1]
  lens: fisheye
R: [1, 0, 0, 0, 1, 0, 0, 0, 2]
T: [0.26, 0, 0]
)";
  auto c = hardware_backend::parse_stereo_calibration(text, "calib.yaml");
  ASSERT_FALSE(c);
  std::string all;
  for (const auto& e : c.error()) all += e + "\n";
  for (const char* expected :
       {"calib.yaml:4: left.K: not a camera matrix", "calib.yaml:5: left.D: has 3 numbers",
        "calib.yaml:8: right.image_height: '480.5' is invalid",
        "calib.yaml:10: right.lens: unknown key", "calib.yaml:11: R: not a rotation",
        "calib.yaml:12: T: T.x > 0: the right camera is to the left of the left one"})
    EXPECT_NE(all.find(expected), std::string::npos) << expected << "\nin:\n" << all;
}

}  // namespace
}  // namespace scancrew::hardware_backend
