#include "components/hardware_backend/base_command_link.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

namespace scancrew::hardware_backend {

namespace {

constexpr std::array<uint8_t, 4> kMagic = {'S', 'C', 'V', 'C'};

void put_u32(uint8_t* out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<uint8_t>(v >> (8 * i));
}
void put_u64(uint8_t* out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out[i] = static_cast<uint8_t>(v >> (8 * i));
}
uint32_t get_u32(const uint8_t* in) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(in[i]) << (8 * i);
  return v;
}
uint64_t get_u64(const uint8_t* in) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(in[i]) << (8 * i);
  return v;
}

}  // namespace

std::array<uint8_t, kVelocityDatagramBytes> encode_velocity_datagram(const VelocityDatagram& d) {
  std::array<uint8_t, kVelocityDatagramBytes> out{};
  std::copy(kMagic.begin(), kMagic.end(), out.begin());
  out[4] = kVelocityDatagramVersion;
  put_u32(&out[8], d.robot_id);
  put_u32(&out[12], d.seq);
  put_u64(&out[16], static_cast<uint64_t>(d.stamp_ns));
  put_u64(&out[24], std::bit_cast<uint64_t>(d.vx_mps));
  put_u64(&out[32], std::bit_cast<uint64_t>(d.vy_mps));
  put_u64(&out[40], std::bit_cast<uint64_t>(d.vz_mps));
  put_u64(&out[48], std::bit_cast<uint64_t>(d.yaw_rate_radps));
  return out;
}

std::string_view to_string(DatagramError error) {
  switch (error) {
    case DatagramError::kWrongSize:
      return "wrong size";
    case DatagramError::kBadMagic:
      return "bad magic";
    case DatagramError::kUnsupportedVersion:
      return "unsupported version";
  }
  return "?";
}

Result<VelocityDatagram, DatagramError> decode_velocity_datagram(std::span<const uint8_t> bytes) {
  if (bytes.size() != kVelocityDatagramBytes) return make_unexpected(DatagramError::kWrongSize);
  if (!std::equal(kMagic.begin(), kMagic.end(), bytes.begin()))
    return make_unexpected(DatagramError::kBadMagic);
  if (bytes[4] != kVelocityDatagramVersion)
    return make_unexpected(DatagramError::kUnsupportedVersion);
  const uint8_t* p = bytes.data();
  VelocityDatagram d;
  d.robot_id = get_u32(p + 8);
  d.seq = get_u32(p + 12);
  d.stamp_ns = static_cast<int64_t>(get_u64(p + 16));
  d.vx_mps = std::bit_cast<double>(get_u64(p + 24));
  d.vy_mps = std::bit_cast<double>(get_u64(p + 32));
  d.vz_mps = std::bit_cast<double>(get_u64(p + 40));
  d.yaw_rate_radps = std::bit_cast<double>(get_u64(p + 48));
  return d;
}

bool BaseCommandLink::valid_ipv4(const std::string& host) {
  in_addr addr{};
  return ::inet_pton(AF_INET, host.c_str(), &addr) == 1;
}

Result<BaseCommandLink, std::string> BaseCommandLink::open(const std::string& host, uint16_t port) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &to.sin_addr) != 1)
    return make_unexpected("'" + host + "' is not an IPv4 address");
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0)
    return make_unexpected("cannot create a UDP socket (" + std::generic_category().message(errno) +
                           ")");
  BaseCommandLink link(fd);  // closes the socket on the error below
  // connect(): fixes the destination, and reports ICMP errors on later sends
  // (the sockets API takes a sockaddr*)
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof(to)) != 0)
    return make_unexpected(std::generic_category().message(errno));
  return link;
}

BaseCommandLink::~BaseCommandLink() {
  close();
}

BaseCommandLink::BaseCommandLink(BaseCommandLink&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), seq_(other.seq_.load(std::memory_order_relaxed)) {}

BaseCommandLink& BaseCommandLink::operator=(BaseCommandLink&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
    seq_.store(other.seq_.load(std::memory_order_relaxed), std::memory_order_relaxed);
  }
  return *this;
}

void BaseCommandLink::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

Result<void, std::string> BaseCommandLink::send(uint32_t robot_id, int64_t stamp_ns, double vx_mps,
                                                double vy_mps, double vz_mps,
                                                double yaw_rate_radps) {
  VelocityDatagram d;
  d.robot_id = robot_id;
  d.seq = seq_.fetch_add(1, std::memory_order_relaxed) + 1;
  d.stamp_ns = stamp_ns;
  d.vx_mps = vx_mps;
  d.vy_mps = vy_mps;
  d.vz_mps = vz_mps;
  d.yaw_rate_radps = yaw_rate_radps;
  const auto bytes = encode_velocity_datagram(d);
  const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
  if (n == static_cast<ssize_t>(bytes.size())) return {};
  if (n >= 0) return make_unexpected(std::string("short send"));
  return make_unexpected(std::generic_category().message(errno));
}

}  // namespace scancrew::hardware_backend
