// The coverage plot of a mission (plots.hpp): coverage (%) over time per robot with the
// 90 % and 95 % levels, and the ISEs left per robot on a panel below, sharing the time axis;
// the first robot's lines solid, the others' dashed, each in its own pattern.

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>

#include "report/plot_canvas.hpp"
#include "report/plots.hpp"

namespace scancrew::report {
namespace {

using canvas::Align;

// Layout, in units of long_side_px / 1000.
constexpr double kAspect = 0.7;  // height / width
constexpr double kLeftMargin = 95, kRightColumn = 170, kTitleBand = 60, kBottomBand = 70;
constexpr double kPanelGap = 40;
constexpr int kTimeTicks = 8;            // about as many intervals on the time axis
constexpr double kTopPanelShare = 0.62;  // of the height the two panels share
constexpr double kLevels[] = {90, 95};   // coverage levels drawn dashed, %

const cv::Scalar ink(30, 30, 30);
const cv::Scalar white(255, 255, 255);
const cv::Scalar grid_colour(232, 232, 232);
const cv::Scalar frame_colour(120, 120, 120);

cv::Scalar robot_bgr(uint32_t robot_id) {
  const auto rgb = robot_colour_rgb(robot_id);
  return {static_cast<double>(rgb[2]), static_cast<double>(rgb[1]), static_cast<double>(rgb[0])};
}

// A plot panel: a pixel rectangle showing [t0, t1] x [v0, v1].
struct Panel {
  cv::Rect2d px;
  double t0 = 0, t1 = 1, v0 = 0, v1 = 1;
  double min_v_step = 0;  // 1 for counts
  cv::Point2d at(double t, double v) const {
    return {px.x + (t - t0) / (t1 - t0) * px.width,
            px.y + px.height - (v - v0) / (v1 - v0) * px.height};
  }
};

// Grid, frame, y ticks with labels, x ticks (labels only when x_labels), the y axis label.
void draw_axes(cv::Mat& img, const Panel& p, const std::string& y_label, bool x_labels,
               const canvas::Style& st) {
  double x_step = 1, y_step = 1;
  const auto xs = canvas::ticks(p.t0, p.t1, kTimeTicks, &x_step);
  const auto ys =
      canvas::ticks(p.v0, p.v1, p.px.height > 250 * st.unit ? 5 : 4, &y_step, p.min_v_step);
  const double label = st.font(0.5);
  const int thin = st.thickness(1);
  for (const double v : ys) {
    const cv::Point2d a = p.at(p.t0, v), b = p.at(p.t1, v);
    cv::line(img, canvas::fixed(a), canvas::fixed(b), grid_colour, thin, cv::LINE_AA,
             canvas::kShift);
    cv::line(img, canvas::fixed(a), canvas::fixed(a - cv::Point2d(6 * st.unit, 0)), frame_colour,
             thin, cv::LINE_AA, canvas::kShift);
    canvas::text(img, canvas::tick_label(v, y_step), a + cv::Point2d(-10 * st.unit, 6 * st.unit),
                 label, ink, thin, Align::kRight);
  }
  for (const double t : xs) {
    const cv::Point2d a = p.at(t, p.v0), b = p.at(t, p.v1);
    cv::line(img, canvas::fixed(a), canvas::fixed(b), grid_colour, thin, cv::LINE_AA,
             canvas::kShift);
    cv::line(img, canvas::fixed(a), canvas::fixed(a + cv::Point2d(0, 6 * st.unit)), frame_colour,
             thin, cv::LINE_AA, canvas::kShift);
    if (x_labels)
      canvas::text(img, canvas::tick_label(t, x_step), a + cv::Point2d(0, 26 * st.unit), label, ink,
                   thin, Align::kCentre);
  }
  cv::rectangle(img, canvas::fixed(p.px.tl()), canvas::fixed(p.px.br()), frame_colour, thin,
                cv::LINE_AA, canvas::kShift);
  canvas::vertical_text(img, y_label, {28 * st.unit, p.px.y + p.px.height / 2}, st.font(0.55), ink,
                        st.thickness(1.4));
}

// no mission lasts this long (317 years): beyond it a file is corrupt or hostile
constexpr double kMaxTimeS = 1e10;

std::string check_inputs(const std::vector<CoverageSample>& samples, const PlotOptions& options) {
  if (options.long_side_px < 200 || options.long_side_px > 20000)
    return "long_side_px " + std::to_string(options.long_side_px) + " not in [200, 20000]";
  for (size_t i = 0; i < samples.size(); ++i) {
    const std::string which =
        "coverage sample " + std::to_string(i) + " (robot " + std::to_string(samples[i].robot_id);
    if (!std::isfinite(samples[i].t_s) || !std::isfinite(samples[i].coverage))
      return which + ") is not finite";
    if (std::abs(samples[i].t_s) > kMaxTimeS) return which + "): time beyond ±1e10 s";
  }
  return {};
}

// The plot's data: the samples per robot and the axes' ranges (time in s).
struct Series {
  std::map<uint32_t, std::vector<CoverageSample>> robots;
  double t_min = 0, t_max = 1, ise_top = 1;
};

// Groups the samples by robot and sets the axes' ranges, each ending on a tick.
Series gather_series(const std::vector<CoverageSample>& samples) {
  // each robot's samples in time order; the ranges of time and of ISEs left
  Series series;
  auto& robots = series.robots;
  for (const CoverageSample& s : samples) robots[s.robot_id].push_back(s);
  double t_min = samples.front().t_s, t_max = t_min;
  uint64_t ises_max = 0;
  for (auto& [id, list] : robots) {
    std::stable_sort(
        list.begin(), list.end(),
        [](const CoverageSample& a, const CoverageSample& b) { return a.t_s < b.t_s; });
    t_min = std::min(t_min, list.front().t_s);
    t_max = std::max(t_max, list.back().t_s);
    for (const CoverageSample& s : list) ises_max = std::max(ises_max, s.ises_left);
  }
  t_min = std::min(t_min, 0.0);  // missions start at t = 0
  if (t_max <= t_min) t_max = t_min + 1;
  double t_step = 1;  // the time axis ends on a tick
  canvas::ticks(t_min, t_max, kTimeTicks, &t_step);
  t_max = std::ceil(t_max / t_step - 1e-9) * t_step;
  double ise_step = 1;
  canvas::ticks(0, std::max<double>(1, static_cast<double>(ises_max)), 4, &ise_step, 1);
  series.ise_top =
      std::max(1.0, std::ceil(static_cast<double>(ises_max) / ise_step - 1e-9) * ise_step);
  series.t_min = t_min;
  series.t_max = t_max;
  return series;
}

// Draws the coverage levels as dashed lines across the coverage panel, each labelled.
void draw_levels(cv::Mat& img, const Panel& cov, const canvas::Style& st) {
  // the 90 % and 95 % levels, labelled on a white box at the left where coverage is still low
  const cv::Scalar level_colour(110, 110, 110);
  for (const double level : kLevels) {
    const cv::Point2d a = cov.at(cov.t0, level), b = cov.at(cov.t1, level);
    canvas::dashed_line(img, a, b, level_colour, st.thickness(1.5), 10 * st.unit, 6 * st.unit);
  }
  for (const double level : kLevels) {
    const std::string label = canvas::tick_label(level, 1) + "%";
    const double font = st.font(0.42);
    const cv::Size size = canvas::text_size(label, font, st.thickness(1));
    const cv::Point2d at = cov.at(cov.t0, level) + cv::Point2d(14 * st.unit, size.height / 2.0);
    cv::rectangle(
        img, canvas::fixed(at + cv::Point2d(-3 * st.unit, 2 * st.unit)),
        canvas::fixed(at + cv::Point2d(size.width + 3 * st.unit, -size.height - 2 * st.unit)),
        white, cv::FILLED, cv::LINE_8, canvas::kShift);
    canvas::text(img, label, at, font, level_colour, st.thickness(1));
  }
}

// Each robot's line pattern, by its rank among the plotted robots: the first solid, the
// others dashed (dash, gap, phase in units), so that robots whose curves coincide (in a
// distributed run every robot ends with the team's map) all show.
struct Dash {
  double dash = 0, gap = 0, phase = 0;  // dash 0: solid
};
constexpr Dash kDashes[] = {{0, 0, 0}, {14, 12, 0}, {5, 9, 2}, {22, 8, 11}, {9, 5, 4}};

Dash dash_of(size_t rank) {
  return kDashes[rank % std::size(kDashes)];
}

// A polyline in the robot's pattern; the dashes run on across its vertices.
void draw_polyline(cv::Mat& img, const std::vector<cv::Point2d>& pts, const cv::Scalar& colour,
                   int thickness, Dash d, double unit) {
  if (d.dash <= 0) {
    std::vector<cv::Point> fixed;
    fixed.reserve(pts.size());
    for (const cv::Point2d& p : pts) fixed.push_back(canvas::fixed(p));
    cv::polylines(img, fixed, false, colour, thickness, cv::LINE_AA, canvas::kShift);
    return;
  }
  const double period = (d.dash + d.gap) * unit;
  double s = d.phase * unit;  // distance along the line, in the pattern
  for (size_t i = 1; i < pts.size(); ++i) {
    const cv::Point2d a = pts[i - 1], b = pts[i];
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    if (length <= 0) continue;
    const cv::Point2d dir = (b - a) * (1.0 / length);
    for (double at = 0; at < length;) {
      const double in = std::fmod(s + at, period);
      const double left = in < d.dash * unit ? d.dash * unit - in : period - in;
      const double e = std::min(length, at + left);
      if (in < d.dash * unit)
        cv::line(img, canvas::fixed(a + dir * at), canvas::fixed(a + dir * e), colour, thickness,
                 cv::LINE_AA, canvas::kShift);
      at = e;
    }
    s += length;
  }
}

// Draws each robot's coverage curve and its ISEs-left steps, each robot in its pattern.
void draw_series(cv::Mat& img, const std::map<uint32_t, std::vector<CoverageSample>>& robots,
                 const Panel& cov, const Panel& ise, const canvas::Style& st) {
  const int line = st.thickness(2.5);
  size_t rank = 0;
  for (const auto& [id, list] : robots) {
    std::vector<cv::Point2d> c, e;
    c.reserve(list.size());
    e.reserve(2 * list.size());
    for (size_t i = 0; i < list.size(); ++i) {
      c.push_back(cov.at(list[i].t_s, 100 * list[i].coverage));
      const double v = static_cast<double>(list[i].ises_left);
      if (i > 0) e.push_back(ise.at(list[i].t_s, static_cast<double>(list[i - 1].ises_left)));
      e.push_back(ise.at(list[i].t_s, v));
    }
    draw_polyline(img, c, robot_bgr(id), line, dash_of(rank), st.unit);
    draw_polyline(img, e, robot_bgr(id), line, dash_of(rank), st.unit);
    ++rank;
  }
}

// Draws the title at the top and the robots' legend in the right column.
void draw_title_and_legend(cv::Mat& img, const std::string& title,
                           const std::map<uint32_t, std::vector<CoverageSample>>& robots,
                           const canvas::Style& st) {
  const int width = img.cols, height = img.rows;
  // title and legend
  canvas::text(img, title, {30 * st.unit, 38 * st.unit},
               canvas::fit_font(title, st.font(0.75), st.thickness(2), width - 60 * st.unit), ink,
               st.thickness(2));
  const double x0 = width - (kRightColumn - 25) * st.unit;
  double y = (kTitleBand + 20) * st.unit;
  const double row = 28 * st.unit;
  canvas::text(img, "robots", {x0, y}, st.font(0.6), ink, st.thickness(1.6));
  y += row;
  size_t shown = 0;
  for (const auto& [id, list] : robots) {
    if (y > height - kBottomBand * st.unit && shown + 1 < robots.size()) {
      canvas::text(img, std::to_string(robots.size() - shown) + " more robots", {x0, y},
                   st.font(0.55), ink, st.thickness(1));
      break;
    }
    const double mid = y - 6 * st.unit;
    draw_polyline(img, {{x0, mid}, {x0 + 36 * st.unit, mid}}, robot_bgr(id), st.thickness(4),
                  dash_of(shown), st.unit);
    canvas::text(img, "robot " + std::to_string(id), {x0 + 46 * st.unit, y}, st.font(0.55), ink,
                 st.thickness(1));
    y += row;
    ++shown;
  }
}

}  // namespace

Result<void, std::string> write_coverage_png(const std::vector<CoverageSample>& samples,
                                             const std::string& out_png,
                                             const PlotOptions& options) {
  if (std::string e = check_inputs(samples, options); !e.empty())
    return make_unexpected("coverage plot '" + out_png + "': " + e);
  const std::string title = options.title.empty() ? "Coverage over time" : options.title;
  const int width = options.long_side_px;
  const int height = static_cast<int>(std::lround(width * kAspect));
  if (samples.empty())
    return canvas::write_png(canvas::no_data(width, height, title, "no coverage samples"), out_png);

  const Series series = gather_series(samples);
  const canvas::Style st{.unit = width / 1000.0};
  cv::Mat img(height, width, CV_8UC3, white);
  const double left = kLeftMargin * st.unit;
  const double plot_w = width - left - kRightColumn * st.unit;
  const double panels_h = height - (kTitleBand + kBottomBand + kPanelGap) * st.unit;
  const double top_h = panels_h * kTopPanelShare;
  Panel cov{.px = {left, kTitleBand * st.unit, plot_w, top_h},
            .t0 = series.t_min,
            .t1 = series.t_max,
            .v0 = 0,
            .v1 = 100};
  Panel ise{.px = {left, (kTitleBand + kPanelGap) * st.unit + top_h, plot_w, panels_h - top_h},
            .t0 = series.t_min,
            .t1 = series.t_max,
            .v0 = 0,
            .v1 = series.ise_top,
            .min_v_step = 1};
  draw_axes(img, cov, "coverage (%)", false, st);
  draw_axes(img, ise, "ISEs left", true, st);
  canvas::text(img, "time (s)", {left + plot_w / 2, height - 14 * st.unit}, st.font(0.55), ink,
               st.thickness(1.4), Align::kCentre);

  draw_levels(img, cov, st);
  draw_series(img, series.robots, cov, ise, st);
  draw_title_and_legend(img, title, series.robots, st);
  return canvas::write_png(img, out_png);
}

}  // namespace scancrew::report
