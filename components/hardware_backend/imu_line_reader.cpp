#include "components/hardware_backend/imu_line_reader.hpp"

#include <array>
#include <charconv>
#include <cmath>

namespace scancrew::hardware_backend {

std::optional<ImuReading> parse_imu_line(std::string_view line) {
  constexpr std::string_view kPrefix = "IMU,";
  if (!line.starts_with(kPrefix)) return std::nullopt;
  line.remove_prefix(kPrefix.size());
  std::array<double, 6> v{};
  for (size_t i = 0; i < v.size(); ++i) {
    const char* begin = line.data();
    const char* end = line.data() + line.size();
    // from_chars takes no leading '+'; accept it as printf("%+f") writes it
    if (begin != end && *begin == '+') {
      ++begin;
      if (begin != end && *begin == '-') return std::nullopt;
    }
    const auto [ptr, ec] = std::from_chars(begin, end, v[i]);
    if (ec != std::errc() || ptr == begin || !std::isfinite(v[i])) return std::nullopt;
    line.remove_prefix(static_cast<size_t>(ptr - line.data()));
    const bool last = i + 1 == v.size();
    if (last) {
      if (!line.empty()) return std::nullopt;
    } else {
      if (line.empty() || line.front() != ',') return std::nullopt;
      line.remove_prefix(1);
    }
  }
  ImuReading r;
  r.linear_acceleration_mps2 = {v[0], v[1], v[2]};
  r.angular_velocity_radps = {v[3], v[4], v[5]};
  return r;
}

std::optional<ImuReading> ImuLineReader::end_line() {
  if (discarding_) {  // the end of an overlong line, already counted
    discarding_ = false;
    line_.clear();
    return std::nullopt;
  }
  std::string_view line(line_);
  if (line.ends_with('\r')) line.remove_suffix(1);
  std::optional<ImuReading> r;
  if (!line.empty()) {
    r = parse_imu_line(line);
    if (r)
      ++stats_.samples;
    else
      ++stats_.malformed;
  }
  line_.clear();
  return r;
}

}  // namespace scancrew::hardware_backend
