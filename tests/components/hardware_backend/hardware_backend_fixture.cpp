// The hardware backend tests' fixture and loopback fakes (hardware_backend_fixture.hpp): the
// recorder's registration, the temporary directory, calibration files, random-dot stereo
// pairs and the UDP socket standing in for the base.

#include "tests/components/hardware_backend/hardware_backend_fixture.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "executors/registry.hpp"

namespace scancrew::hardware_backend::fixture {
namespace {

std::string list(const std::vector<double>& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
  s << "]";
  return s.str();
}

}  // namespace

SCANCREW_REGISTER_COMPONENT(HwRecorder, "test_hw_recorder")

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "scancrew_hw_XXXXXX").string();
  const char* made = ::mkdtemp(pattern.data());
  EXPECT_NE(made, nullptr);
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
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

size_t open_descriptors() {
  return static_cast<size_t>(std::distance(std::filesystem::directory_iterator("/proc/self/fd"),
                                           std::filesystem::directory_iterator()));
}

UdpReceiver::UdpReceiver() {
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

UdpReceiver::~UdpReceiver() {
  ::close(fd_);
}

std::optional<std::vector<uint8_t>> UdpReceiver::receive(std::chrono::milliseconds timeout) {
  pollfd p{fd_, POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(timeout.count())) != 1) return std::nullopt;
  std::vector<uint8_t> buffer(512);
  const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), 0);
  if (n < 0) return std::nullopt;
  buffer.resize(static_cast<size_t>(n));
  return buffer;
}

}  // namespace scancrew::hardware_backend::fixture
