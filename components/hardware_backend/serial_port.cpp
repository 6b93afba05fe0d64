#include "components/hardware_backend/serial_port.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <system_error>
#include <utility>

#include "components/hardware_backend/device_error.hpp"

namespace scancrew::hardware_backend {

namespace {

struct BaudRate {
  uint32_t baud;
  speed_t speed;
};

constexpr std::array<BaudRate, 19> kBaudRates = {{{1200, B1200},
                                                  {2400, B2400},
                                                  {4800, B4800},
                                                  {9600, B9600},
                                                  {19200, B19200},
                                                  {38400, B38400},
                                                  {57600, B57600},
                                                  {115200, B115200},
                                                  {230400, B230400},
                                                  {460800, B460800},
                                                  {500000, B500000},
                                                  {576000, B576000},
                                                  {921600, B921600},
                                                  {1000000, B1000000},
                                                  {1500000, B1500000},
                                                  {2000000, B2000000},
                                                  {2500000, B2500000},
                                                  {3000000, B3000000},
                                                  {4000000, B4000000}}};

}  // namespace

bool SerialPort::supported_baud(uint32_t baud) {
  for (const BaudRate& b : kBaudRates)
    if (b.baud == baud) return true;
  return false;
}

std::string SerialPort::supported_bauds() {
  std::string list;
  for (const BaudRate& b : kBaudRates) list += (list.empty() ? "" : ", ") + std::to_string(b.baud);
  return list;
}

Result<SerialPort, std::string> SerialPort::open(const std::string& path, uint32_t baud) {
  speed_t speed = B0;
  for (const BaudRate& b : kBaudRates)
    if (b.baud == baud) speed = b.speed;
  if (speed == B0)
    return make_unexpected("unsupported baud rate " + std::to_string(baud) +
                           "; allowed: " + supported_bauds());
  if (path.empty()) return make_unexpected(std::string("no device given"));
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return make_unexpected(device_open_error(errno, "dialout"));
  SerialPort port(fd);  // closes the descriptor on every error below
  termios tio{};
  if (::isatty(fd) == 0 || ::tcgetattr(fd, &tio) != 0)
    return make_unexpected(std::string("not a serial port (not a terminal device)"));
  ::cfmakeraw(&tio);  // no echo, no line editing, no CR/LF translation, 8 bits
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | PARENB | CRTSCTS);  // 8N1, no hardware flow control
  tio.c_iflag &= ~(IXON | IXOFF | IXANY);       // no software flow control
  tio.c_cc[VMIN] = 0;                           // read() returns what is there
  tio.c_cc[VTIME] = 0;
  if (::cfsetispeed(&tio, speed) != 0 || ::cfsetospeed(&tio, speed) != 0 ||
      ::tcsetattr(fd, TCSANOW, &tio) != 0)
    return make_unexpected("cannot configure the port (" + device_open_error(errno, "dialout") +
                           ")");
  (void)::tcflush(fd, TCIFLUSH);  // stale input from before we opened it
  return port;
}

SerialPort::~SerialPort() {
  close();
}

SerialPort::SerialPort(SerialPort&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

void SerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

Result<size_t, std::string> SerialPort::read_available(std::span<char> buffer) {
  const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
  if (n >= 0) return static_cast<size_t>(n);
  if (errno == EAGAIN || errno == EINTR) return size_t{0};
  return make_unexpected(device_open_error(errno, "dialout"));
}

}  // namespace scancrew::hardware_backend
