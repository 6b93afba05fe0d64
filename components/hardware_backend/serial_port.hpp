#pragma once

// SerialPort: a serial device (/dev/ttyUSB0, /dev/ttyACM0, a pseudo-terminal in the
// tests) opened with POSIX open() and termios: raw mode (no echo, no line editing, no
// CR/LF translation), 8N1, no flow control, the given baud rate, non-blocking reads.
// Input queued before open() is flushed. The descriptor is closed by the destructor.
//
// Thread safety: one thread at a time. Allocation: none in read_available().

#include <cstdint>
#include <span>
#include <string>

#include "core/result.hpp"

namespace scancrew::hardware_backend {

class SerialPort {
 public:
  // Opens `path` at `baud`. The error is the cause only ("no such device",
  // "permission denied; ...", "not a serial port"); the caller names the parameter.
  static Result<SerialPort, std::string> open(const std::string& path, uint32_t baud);
  // The baud rates termios offers, as text for messages ("1200, 2400, ...").
  static bool supported_baud(uint32_t baud);
  static std::string supported_bauds();

  SerialPort() = default;
  ~SerialPort();
  SerialPort(SerialPort&& other) noexcept;
  SerialPort& operator=(SerialPort&& other) noexcept;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  bool is_open() const { return fd_ >= 0; }
  // Reads what is waiting, without blocking: the byte count (0 when nothing is waiting),
  // or the cause of a read error (a device that went away reads as an I/O error).
  Result<size_t, std::string> read_available(std::span<char> buffer);

 private:
  explicit SerialPort(int fd) : fd_(fd) {}
  void close();

  int fd_ = -1;
};

}  // namespace scancrew::hardware_backend
