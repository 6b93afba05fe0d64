#include "report/plot_canvas.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace scancrew::report::canvas {

namespace {
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
}

int Style::thickness(double units) const {
  return std::max(1, static_cast<int>(std::lround(units * unit)));
}

std::string ascii(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return out;
}

cv::Size text_size(const std::string& s, double font_scale, int thickness) {
  int baseline = 0;
  return cv::getTextSize(ascii(s), kFont, font_scale, thickness, &baseline);
}

double fit_font(const std::string& s, double font_scale, int thickness, double max_width_px) {
  const int width = text_size(s, font_scale, thickness).width;
  return width <= max_width_px || width == 0 ? font_scale : font_scale * max_width_px / width;
}

void text(cv::Mat& img, const std::string& s, cv::Point2d at, double font_scale,
          const cv::Scalar& colour, int thickness, Align align) {
  const cv::Size size = text_size(s, font_scale, thickness);
  double x = at.x;
  if (align == Align::kCentre) x -= size.width / 2.0;
  if (align == Align::kRight) x -= size.width;
  cv::putText(img, ascii(s), cv::Point(static_cast<int>(std::lround(x)), static_cast<int>(at.y)),
              kFont, font_scale, colour, thickness, cv::LINE_AA);
}

void vertical_text(cv::Mat& img, const std::string& s, cv::Point2d at, double font_scale,
                   const cv::Scalar& colour, int thickness) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(ascii(s), kFont, font_scale, thickness, &baseline);
  const int pad = thickness + 2;
  cv::Mat label(size.height + baseline + 2 * pad, size.width + 2 * pad, img.type(),
                cv::Scalar(255, 255, 255));
  cv::putText(label, ascii(s), cv::Point(pad, pad + size.height), kFont, font_scale, colour,
              thickness, cv::LINE_AA);
  cv::Mat turned;
  cv::rotate(label, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect where(static_cast<int>(std::lround(at.x - turned.cols / 2.0)),
                 static_cast<int>(std::lround(at.y - turned.rows / 2.0)), turned.cols, turned.rows);
  const cv::Rect inside = where & cv::Rect(0, 0, img.cols, img.rows);
  if (inside.area() == 0) return;
  turned(cv::Rect(inside.x - where.x, inside.y - where.y, inside.width, inside.height))
      .copyTo(img(inside));
}

cv::Point fixed(cv::Point2d p) {
  constexpr double kScale = 1 << kShift;
  return {static_cast<int>(std::lround(p.x * kScale)), static_cast<int>(std::lround(p.y * kScale))};
}

void dashed_line(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& colour,
                 int thickness, double dash_px, double gap_px) {
  const double length = std::hypot(b.x - a.x, b.y - a.y);
  if (length <= 0 || dash_px <= 0) return;
  const cv::Point2d dir = (b - a) * (1.0 / length);
  for (double s = 0; s < length; s += dash_px + gap_px) {
    const double e = std::min(length, s + dash_px);
    cv::line(img, fixed(a + dir * s), fixed(a + dir * e), colour, thickness, cv::LINE_AA, kShift);
  }
}

double nice_floor(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (const double m : {5.0, 2.0, 1.0})
    if (m * p <= x * (1 + 1e-9)) return m * p;
  return p;
}

std::vector<double> ticks(double lo, double hi, int target, double* step, double min_step) {
  *step = std::max(1.0, min_step);
  // a range with no width, or not finite, has no steps: its one value
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo)) return {std::isfinite(lo) ? lo : 0.0};
  const double n = std::max(1, target);
  const double raw = hi / n - lo / n;  // not (hi - lo) / n: that overflows at ±1e308
  if (!(raw > 0)) return {lo};         // the width underflowed
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  // the nice step nearest to raw (by ratio)
  double s = p;
  for (const double m : {2.0, 5.0, 10.0})
    if (std::abs(std::log(m * p / raw)) < std::abs(std::log(s / raw))) s = m * p;
  if (!(s > 0) || !std::isfinite(s)) return {lo};
  s = std::max(s, min_step);
  *step = s;
  // by index, not by adding s to v: at lo = 1e9 and a width of one ulp, v + s == v (the
  // report of such a coverage.csv looped until it ran out of memory)
  const double first = std::ceil(lo / s - 1e-9), last = std::floor(hi / s + 1e-9);
  constexpr int kMaxTicks = 1000;
  std::vector<double> values;
  for (int i = 0; i < kMaxTicks && first + i <= last; ++i) {
    const double v = (first + i) * s;
    if (!values.empty() && v <= values.back()) break;  // k past the doubles' resolution
    values.push_back(std::abs(v) < s * 1e-9 ? 0.0 : v);
  }
  return values;
}

std::string tick_label(double value, double step) {
  const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

cv::Mat no_data(int width_px, int height_px, const std::string& title, const std::string& reason) {
  cv::Mat img(height_px, width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const Style st{.unit = std::max(width_px, height_px) / 1000.0};
  text(img, title, {st.unit * 30, st.unit * 40},
       fit_font(title, st.font(0.75), st.thickness(2), width_px - 60 * st.unit),
       cv::Scalar(30, 30, 30), st.thickness(2));
  text(img, "no data", {width_px / 2.0, height_px / 2.0}, st.font(1.6), cv::Scalar(150, 150, 150),
       st.thickness(3), Align::kCentre);
  text(img, reason, {width_px / 2.0, height_px / 2.0 + st.unit * 45}, st.font(0.6),
       cv::Scalar(110, 110, 110), st.thickness(1), Align::kCentre);
  return img;
}

Result<void, std::string> write_png(const cv::Mat& img, const std::string& out_png) {
  const std::filesystem::path path(out_png);
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".png") return make_unexpected("cannot write '" + out_png + "': not a .png file");
  std::error_code ec;
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : ".";
  if (!std::filesystem::is_directory(dir, ec))
    return make_unexpected("cannot write '" + out_png + "': folder '" + dir.string() +
                           "' does not exist");
  try {
    if (!cv::imwrite(out_png, img)) return make_unexpected("cannot write '" + out_png + "'");
  } catch (const cv::Exception& e) {
    return make_unexpected("cannot write '" + out_png + "': " + e.what());
  }
  return {};
}

}  // namespace scancrew::report::canvas
