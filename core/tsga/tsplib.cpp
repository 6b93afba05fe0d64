#include "core/tsga/tsplib.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>
#include <vector>

namespace scancrew::tsga {

namespace {

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

bool parse_size(std::string_view text, size_t& out) {
  const auto* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end;
}

bool parse_double(std::string_view text, double& out) {
  const auto* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end;
}

class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  Result<TsplibInstance, std::string> run(std::istream& in) {
    std::string line;
    while (std::getline(in, line)) {
      ++line_no_;
      const std::string_view text = trim(line);
      if (text.empty()) continue;
      if (in_section_) {
        if (auto ok = read_values(text); !ok) return make_unexpected(ok.error());
      } else {
        if (auto ok = read_header(text); !ok) return make_unexpected(ok.error());
      }
      if (done_) break;
    }
    if (!in_section_) return make_unexpected(at(line_no_) + "no EDGE_WEIGHT_SECTION");
    if (values_.size() != n_ * n_)
      return make_unexpected(at(line_no_) + "EDGE_WEIGHT_SECTION ends with " +
                             std::to_string(values_.size()) + " values; DIMENSION " +
                             std::to_string(n_) + " needs " + std::to_string(n_ * n_));
    auto costs = CostMatrix::from_values(n_, std::move(values_));
    if (!costs) return make_unexpected(costs.error());
    instance_.costs = std::move(costs).value();
    return std::move(instance_);
  }

 private:
  std::string at(int line) const { return source_ + ":" + std::to_string(line) + ": "; }

  Result<void, std::string> read_header(std::string_view text) {
    if (text == "EOF") return make_unexpected(at(line_no_) + "EOF before EDGE_WEIGHT_SECTION");
    const auto colon = text.find(':');
    const std::string_view key = trim(text.substr(0, colon));
    const std::string_view value =
        colon == std::string_view::npos ? std::string_view{} : trim(text.substr(colon + 1));
    if (key == "EDGE_WEIGHT_SECTION") return begin_section(value);
    if (colon == std::string_view::npos)
      return make_unexpected(at(line_no_) +
                             "expected 'KEYWORD: value' or EDGE_WEIGHT_SECTION, got '" +
                             std::string(text) + "'");
    if (key == "NAME") {
      instance_.name = value;
    } else if (key == "COMMENT") {
      if (!instance_.comment.empty()) instance_.comment += "\n";
      instance_.comment += value;
    } else if (key == "TYPE") {
      if (value != "ATSP" && value != "TSP")
        return make_unexpected(at(line_no_) + "TYPE " + std::string(value) +
                               " is not supported; allowed: ATSP, TSP");
    } else if (key == "EDGE_WEIGHT_TYPE") {
      if (value != "EXPLICIT")
        return make_unexpected(at(line_no_) + "EDGE_WEIGHT_TYPE " + std::string(value) +
                               " is not supported; allowed: EXPLICIT");
    } else if (key == "EDGE_WEIGHT_FORMAT") {
      if (value != "FULL_MATRIX")
        return make_unexpected(at(line_no_) + "EDGE_WEIGHT_FORMAT " + std::string(value) +
                               " is not supported; allowed: FULL_MATRIX");
    } else if (key == "DIMENSION") {
      if (!parse_size(value, n_) || n_ == 0 || n_ > kMaxTsplibDimension)
        return make_unexpected(at(line_no_) + "DIMENSION '" + std::string(value) +
                               "' is not an integer in [1, " + std::to_string(kMaxTsplibDimension) +
                               "]");
    } else if (key != "DISPLAY_DATA_TYPE") {
      return make_unexpected(at(line_no_) + "unsupported keyword '" + std::string(key) + "'");
    }
    return {};
  }

  Result<void, std::string> begin_section(std::string_view rest) {
    if (n_ == 0) return make_unexpected(at(line_no_) + "EDGE_WEIGHT_SECTION before DIMENSION");
    in_section_ = true;
    values_.reserve(n_ * n_);
    return rest.empty() ? Result<void, std::string>{} : read_values(rest);
  }

  Result<void, std::string> read_values(std::string_view text) {
    while (!text.empty()) {
      const auto end = text.find_first_of(" \t");
      const std::string_view token = text.substr(0, end);
      text = end == std::string_view::npos ? std::string_view{} : trim(text.substr(end));
      if (token == "EOF") {
        done_ = true;
        return {};
      }
      double v = 0.0;
      if (!parse_double(token, v))
        return make_unexpected(at(line_no_) + "'" + std::string(token) +
                               "' is not a number (EDGE_WEIGHT_SECTION value " +
                               std::to_string(values_.size() + 1) + ")");
      if (!std::isfinite(v))
        return make_unexpected(at(line_no_) + "'" + std::string(token) + "' is not finite");
      if (values_.size() == n_ * n_)
        return make_unexpected(at(line_no_) + "more than the " + std::to_string(n_ * n_) +
                               " values of DIMENSION " + std::to_string(n_));
      values_.push_back(v);
    }
    return {};
  }

  std::string source_;
  TsplibInstance instance_;
  size_t n_ = 0;
  int line_no_ = 0;
  bool in_section_ = false;
  bool done_ = false;
  std::vector<double> values_;
};

}  // namespace

Result<TsplibInstance, std::string> parse_tsplib(std::istream& in, const std::string& source) {
  return Parser(source).run(in);
}

Result<TsplibInstance, std::string> load_tsplib(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_unexpected(path + ": cannot open");
  return parse_tsplib(in, path);
}

}  // namespace scancrew::tsga
