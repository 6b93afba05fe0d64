#pragma once

// The hardware backend tests' fixture and loopback fakes (test_stereo_cameras.cpp,
// test_imu_and_base_link.cpp), on sim time with the step executor: cameras are image
// sequences written with cv::imwrite, the IMU is a pseudo-terminal whose master end the test
// writes, and the base is a UDP socket the test binds on 127.0.0.1. Every wait on the
// outside world is bounded (kWaitLimit). The recorder component ("test_hw_recorder") is
// registered once, in hardware_backend_fixture.cpp.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>
#include <vector>

#include "components/hardware_backend/hardware_backend.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::hardware_backend::fixture {

inline constexpr std::chrono::seconds kWaitLimit{2};  // the longest any test waits for a device

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

// A temporary directory, removed with everything in it.
class TempDir {
 public:
  TempDir();
  ~TempDir();
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

// The calibration file's text (the format of launch_cfg/calibration/example_stereo.yaml).
std::string calibration_yaml(const Calibration& c);

// A random-dot scene seen by a rectified pair: right(x) = left(x + d) (disparity d).
struct StereoImages {
  cv::Mat left, right;
};
StereoImages make_pair(int width, int height, int disparity_px, uint32_t seed);

std::vector<uint8_t> bytes_of(const cv::Mat& m);

// The number of file descriptors this process has open.
size_t open_descriptors();

// A UDP socket on 127.0.0.1, an ephemeral port, closed at the end.
class UdpReceiver {
 public:
  UdpReceiver();
  ~UdpReceiver();
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;
  uint16_t port() const { return port_; }

  // One datagram, or nothing within timeout.
  std::optional<std::vector<uint8_t>> receive(std::chrono::milliseconds timeout);

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
};

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

}  // namespace scancrew::hardware_backend::fixture
