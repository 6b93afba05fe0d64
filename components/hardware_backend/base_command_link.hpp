#pragma once

// BaseCommandLink: velocity commands to the robot base's controller, one UDP datagram per
// command, to a fixed IPv4 endpoint.
//
// Datagram, version 1: 56 bytes, little-endian, no padding beyond what is listed:
//
//   offset size type      field
//        0    4 char[4]   magic "SCVC"
//        4    1 u8        version (1)
//        5    3 u8[3]     reserved, 0
//        8    4 u32       robot id (the launch file's robots[].id)
//       12    4 u32       seq: datagrams sent by this link, from 1, wraps; a gap = a loss
//       16    8 i64       stamp_ns: the command's header.stamp_ns (sender's clock), ns
//       24    8 f64       vx, m/s      (body frame, IEEE 754 binary64)
//       32    8 f64       vy, m/s
//       40    8 f64       vz, m/s      (0 for a ground robot)
//       48    8 f64       yaw rate, rad/s
//
// Datagrams can be lost or reordered; the base should drop one whose seq is not newer than
// the last it applied, and stop on its own when commands stop arriving (a watchdog).
//
// Thread safety: send() may be called from any thread (seq is atomic; a datagram is one
// send()). Allocation: none in send().

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "core/result.hpp"

namespace scancrew::hardware_backend {

inline constexpr size_t kVelocityDatagramBytes = 56;
inline constexpr uint8_t kVelocityDatagramVersion = 1;

struct VelocityDatagram {
  uint32_t robot_id = 0;
  uint32_t seq = 0;
  int64_t stamp_ns = 0;
  double vx_mps = 0, vy_mps = 0, vz_mps = 0;
  double yaw_rate_radps = 0;
};

std::array<uint8_t, kVelocityDatagramBytes> encode_velocity_datagram(const VelocityDatagram& d);

enum class DatagramError : uint8_t { kWrongSize, kBadMagic, kUnsupportedVersion };
std::string_view to_string(DatagramError error);
// The base's side of the protocol (and the tests').
Result<VelocityDatagram, DatagramError> decode_velocity_datagram(std::span<const uint8_t> bytes);

class BaseCommandLink {
 public:
  // True for a dotted-quad IPv4 address ("192.168.1.20").
  static bool valid_ipv4(const std::string& host);
  // A UDP socket connected to host:port. The error is the cause only.
  static Result<BaseCommandLink, std::string> open(const std::string& host, uint16_t port);

  BaseCommandLink() = default;
  ~BaseCommandLink();
  BaseCommandLink(BaseCommandLink&& other) noexcept;
  BaseCommandLink& operator=(BaseCommandLink&& other) noexcept;
  BaseCommandLink(const BaseCommandLink&) = delete;
  BaseCommandLink& operator=(const BaseCommandLink&) = delete;

  bool is_open() const { return fd_ >= 0; }
  // Sends one datagram (seq and robot id are filled in here) without blocking. An error
  // is the cause: a full socket buffer, or "connection refused" after an earlier datagram
  // found nobody listening (ICMP port unreachable).
  Result<void, std::string> send(uint32_t robot_id, int64_t stamp_ns, double vx_mps, double vy_mps,
                                 double vz_mps, double yaw_rate_radps);
  uint32_t last_seq() const { return seq_.load(std::memory_order_relaxed); }

 private:
  explicit BaseCommandLink(int fd) : fd_(fd) {}
  void close();

  int fd_ = -1;
  std::atomic<uint32_t> seq_{0};
};

}  // namespace scancrew::hardware_backend
