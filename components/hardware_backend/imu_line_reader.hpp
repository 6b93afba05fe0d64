#pragma once

// ImuLineReader: turns the byte stream of a serial IMU into samples.
//
// Line protocol (ASCII, one sample per line, C locale):
//
//   IMU,<ax>,<ay>,<az>,<gx>,<gy>,<gz>\n
//
//   ax ay az  specific force in the IMU frame, m/s² (reads about +9.81 on z at rest, z up)
//   gx gy gz  angular velocity in the IMU frame, rad/s
//
// Numbers are decimal floating point (sign, fraction and exponent allowed, finite only),
// separated by single commas, no spaces. A '\r' before the '\n' is accepted; empty lines
// are ignored. Any other line is malformed: counted and skipped. Bytes are buffered until
// their newline arrives, so a line may be split across reads. A line that grows past
// max_line_bytes without a newline is discarded up to the next newline and counted (a
// stream without newlines cannot grow the buffer). The first line after opening a port
// may be the tail of a line: it is counted as malformed like any other.
//
// Thread safety: one thread at a time. Allocation: none after construction.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "interfaces/geometry.hpp"

namespace scancrew::hardware_backend {

struct ImuReading {
  msg::Vec3 linear_acceleration_mps2;
  msg::Vec3 angular_velocity_radps;
};

// One line without its newline; nothing when it is not a valid IMU line.
std::optional<ImuReading> parse_imu_line(std::string_view line);

struct ImuLineStats {
  uint64_t samples = 0;    // valid lines
  uint64_t malformed = 0;  // complete lines that did not parse
  uint64_t overlong = 0;   // lines discarded for exceeding max_line_bytes
};

class ImuLineReader {
 public:
  explicit ImuLineReader(size_t max_line_bytes) : max_line_bytes_(max_line_bytes) {
    line_.reserve(max_line_bytes);
  }

  // Consumes bytes; calls on_sample(const ImuReading&) for each valid complete line.
  template <class OnSample>
  void feed(std::string_view bytes, OnSample&& on_sample) {
    for (const char c : bytes) {
      if (c == '\n') {
        if (std::optional<ImuReading> r = end_line()) on_sample(*r);
        continue;
      }
      if (discarding_) continue;
      if (line_.size() >= max_line_bytes_) {
        discarding_ = true;
        ++stats_.overlong;
        line_.clear();
        continue;
      }
      line_.push_back(c);
    }
  }

  const ImuLineStats& stats() const { return stats_; }
  size_t buffered_bytes() const { return line_.size(); }

 private:
  std::optional<ImuReading> end_line();

  size_t max_line_bytes_;
  std::string line_;
  bool discarding_ = false;
  ImuLineStats stats_;
};

}  // namespace scancrew::hardware_backend
