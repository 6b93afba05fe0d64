#include "report/run_files.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string_view>
#include <system_error>

#include "executors/params_impl.hpp"

namespace scancrew::report {
namespace {

constexpr const char* kPathsHeader = "t_s,robot_id,x_m,y_m,z_m,yaw_rad";
constexpr const char* kCoverageHeader = "t_s,robot_id,coverage,coverage_reachable,ises_left";

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// Writes the header and one line per sample (format_line fills buf); fails with the file
// name and the cause.
template <class Sample, class Format>
Result<void, std::string> write_csv(const std::string& path, const char* header,
                                    const std::vector<Sample>& samples, Format format_line) {
  std::FILE* raw = std::fopen(path.c_str(), "w");
  if (raw == nullptr) {
    const std::error_code ec(errno, std::generic_category());
    return make_unexpected("cannot open '" + path + "' for writing: " + ec.message());
  }
  std::unique_ptr<std::FILE, FileCloser> file(raw);
  std::fprintf(raw, "%s\n", header);
  for (const Sample& s : samples) format_line(raw, s);
  const bool write_failed = std::ferror(raw) != 0;
  if (std::fclose(file.release()) != 0 || write_failed)
    return make_unexpected("writing '" + path + "' failed (disk full or I/O error)");
  return {};
}

// One data line being parsed: its fields, and where it came from for the errors.
class LineFields {
 public:
  LineFields(const std::string& path, size_t line_no, const std::string& line,
             const std::vector<std::string_view>& names)
      : path_(path), line_no_(line_no), names_(names) {
    std::string_view rest(line);
    while (true) {
      const size_t comma = rest.find(',');
      fields_.push_back(rest.substr(0, comma));
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
  }

  // Empty when the line has as many fields as the header, else the error.
  std::string check_count() const {
    if (fields_.size() == names_.size()) return {};
    return where() + ": " + std::to_string(fields_.size()) + " fields, expected " +
           std::to_string(names_.size());
  }

  // Field i as a finite double; on failure error_ names the field.
  double real(size_t i) {
    const std::string_view f = fields_[i];
    double v = 0;
    const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
    if (ec != std::errc() || end != f.data() + f.size() || f.empty())
      fail(i, "is not a number");
    else if (!std::isfinite(v))
      fail(i, "is not finite");
    return v;
  }

  // Field i as an unsigned integer no larger than max.
  uint64_t integer(size_t i, uint64_t max) {
    const std::string_view f = fields_[i];
    uint64_t v = 0;
    const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
    if (ec == std::errc::result_out_of_range || (ec == std::errc() && v > max))
      fail(i, "is out of range [0, " + std::to_string(max) + "]");
    else if (ec != std::errc() || end != f.data() + f.size() || f.empty())
      fail(i, "is not an unsigned integer");
    return v;
  }

  void fail(size_t i, const std::string& what) {
    if (error_.empty())
      error_ = where() + ": field " + std::string(names_[i]) + " '" + std::string(fields_[i]) +
               "' " + what;
  }

  const std::string& error() const { return error_; }

 private:
  std::string where() const { return path_ + ":" + std::to_string(line_no_); }

  const std::string& path_;
  size_t line_no_;
  const std::vector<std::string_view>& names_;
  std::vector<std::string_view> fields_;
  std::string error_;
};

std::vector<std::string_view> split_header(std::string_view header) {
  std::vector<std::string_view> names;
  while (true) {
    const size_t comma = header.find(',');
    names.push_back(header.substr(0, comma));
    if (comma == std::string_view::npos) break;
    header.remove_prefix(comma + 1);
  }
  return names;
}

// Reads the file line by line: checks the header, then hands each non-empty line to
// parse_line(fields), which returns the sample (fields.error() set on failure).
template <class Sample, class Parse>
Result<std::vector<Sample>, std::string> read_csv(const std::string& path, const char* header,
                                                  Parse parse_line) {
  // a regular file of bounded size (a device or a pipe would be read for ever)
  const auto text = read_text_file(path);
  if (!text) return make_unexpected("cannot read '" + path + "': " + text.error());
  std::istringstream in(*text);
  const std::vector<std::string_view> names = split_header(header);
  std::vector<Sample> samples;
  std::string line;
  size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no == 1) {
      if (line != header)
        return make_unexpected(path + ":1: header '" + line.substr(0, 120) + "', expected '" +
                               header + "'");
      continue;
    }
    if (line.empty()) continue;
    LineFields fields(path, line_no, line, names);
    if (std::string e = fields.check_count(); !e.empty()) return make_unexpected(std::move(e));
    Sample s = parse_line(fields);
    if (!fields.error().empty()) return make_unexpected(fields.error());
    samples.push_back(s);
  }
  if (in.bad()) return make_unexpected("reading '" + path + "' failed");
  if (line_no == 0)
    return make_unexpected(path + ": empty file, expected the header '" + std::string(header) +
                           "'");
  return samples;
}

}  // namespace

Result<void, std::string> write_paths_csv(const std::string& path,
                                          const std::vector<PathSample>& samples) {
  return write_csv(path, kPathsHeader, samples, [](std::FILE* f, const PathSample& s) {
    std::fprintf(f, "%.3f,%u,%.4f,%.4f,%.4f,%.4f\n", s.t_s, static_cast<unsigned>(s.robot_id),
                 s.x_m, s.y_m, s.z_m, s.yaw_rad);
  });
}

Result<void, std::string> write_coverage_csv(const std::string& path,
                                             const std::vector<CoverageSample>& samples) {
  return write_csv(path, kCoverageHeader, samples, [](std::FILE* f, const CoverageSample& s) {
    std::fprintf(f, "%.3f,%u,%.5f,%.5f,%llu\n", s.t_s, static_cast<unsigned>(s.robot_id),
                 s.coverage, s.coverage_reachable, static_cast<unsigned long long>(s.ises_left));
  });
}

Result<std::vector<PathSample>, std::string> read_paths_csv(const std::string& path) {
  return read_csv<PathSample>(path, kPathsHeader, [](LineFields& f) {
    PathSample s;
    s.t_s = f.real(0);
    s.robot_id = static_cast<uint32_t>(f.integer(1, std::numeric_limits<uint32_t>::max()));
    s.x_m = f.real(2);
    s.y_m = f.real(3);
    s.z_m = f.real(4);
    s.yaw_rad = f.real(5);
    return s;
  });
}

Result<std::vector<CoverageSample>, std::string> read_coverage_csv(const std::string& path) {
  return read_csv<CoverageSample>(path, kCoverageHeader, [](LineFields& f) {
    CoverageSample s;
    s.t_s = f.real(0);
    s.robot_id = static_cast<uint32_t>(f.integer(1, std::numeric_limits<uint32_t>::max()));
    s.coverage = f.real(2);
    if (f.error().empty() && (s.coverage < 0 || s.coverage > 1)) f.fail(2, "is not in [0, 1]");
    s.coverage_reachable = f.real(3);
    if (f.error().empty() && s.coverage_reachable != -1 &&
        (s.coverage_reachable < 0 || s.coverage_reachable > 1))
      f.fail(3, "is not in [0, 1] (nor -1: not measured)");
    s.ises_left = f.integer(4, std::numeric_limits<uint64_t>::max());
    return s;
  });
}

std::optional<double> time_to_coverage(const std::vector<CoverageSample>& samples, double share,
                                       bool reachable) {
  // samples are in time order; every robot measured at one tick shares its t_s
  for (const CoverageSample& s : samples) {
    const double c = reachable ? s.coverage_reachable : s.coverage;
    if (c >= share) return s.t_s;
  }
  return std::nullopt;
}

}  // namespace scancrew::report
