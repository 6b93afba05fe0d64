#pragma once

// Drawing helpers shared by the mission pictures (plots.cpp, top_view.cpp,
// coverage_plot.cpp): text, dashed lines, tick spacing, the "no data" picture and PNG output.
// Internal to scancrew_mission_report: it includes OpenCV, so only the library's .cpp files
// include it.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace scancrew::report::canvas {

// Sizes scale with the image: one unit is long_side_px / 1000 pixels.
struct Style {
  double unit = 1;
  int thickness(double units) const;  // at least 1 px
  double font(double scale) const { return scale * unit; }
};

enum class Align { kLeft, kCentre, kRight };

// Text with its baseline at y; ASCII only (other bytes become '?').
void text(cv::Mat& img, const std::string& s, cv::Point2d at, double font_scale,
          const cv::Scalar& colour, int thickness, Align align = Align::kLeft);
// Text turned 90 degrees counter-clockwise, centred on at (an axis label).
void vertical_text(cv::Mat& img, const std::string& s, cv::Point2d at, double font_scale,
                   const cv::Scalar& colour, int thickness);
cv::Size text_size(const std::string& s, double font_scale, int thickness);
// font_scale, or less so that s is at most max_width_px wide.
double fit_font(const std::string& s, double font_scale, int thickness, double max_width_px);

// Sub-pixel drawing (4 fractional bits).
cv::Point fixed(cv::Point2d p);
constexpr int kShift = 4;

void dashed_line(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& colour,
                 int thickness, double dash_px, double gap_px);

// Tick values in [lo, hi] of the nice step (1, 2 or 5 times a power of ten) nearest to
// (hi - lo) / target, at least min_step; the step in *step.
std::vector<double> ticks(double lo, double hi, int target, double* step, double min_step = 0);
std::string tick_label(double value, double step);
// The largest 1, 2 or 5 times a power of ten not above x (x > 0).
double nice_floor(double x);

// A white picture with the title and "no data" with the reason below it.
cv::Mat no_data(int width_px, int height_px, const std::string& title, const std::string& reason);

// Checks that out_png ends in .png and its folder exists, then writes; errors name the file.
Result<void, std::string> write_png(const cv::Mat& img, const std::string& out_png);

std::string ascii(const std::string& s);

}  // namespace scancrew::report::canvas
