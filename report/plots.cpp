// The top view of a mission (plots.hpp); the coverage plot is in coverage_plot.cpp.

#include "report/plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "report/plot_canvas.hpp"

namespace scancrew::report {
namespace {

using canvas::Align;

// Layout of the top view, in units of long_side_px / 1000.
constexpr double kLeftMargin = 30, kRightColumn = 190, kTitleBand = 60, kBottomBand = 60;
constexpr double kMinAspect = 0.6;     // the plot's short side is at least this share of its long
constexpr double kDataPadding = 0.04;  // share of the data extent added on each side
constexpr double kMinExtentM = 1;      // a single point still gets a 1 m wide view
// no place a team maps is this far out: beyond it a file is corrupt or hostile (at ±1e308 the
// extent overflowed to inf and the pixel sizes became NaN)
constexpr double kMaxCoordinateM = 1e7;
constexpr uint8_t kLowGrey = 222, kHighGrey = 60;  // mesh grey ramp, lowest to highest z
constexpr double kDownFacing = 0.5;  // faces whose normal is > 60° below the horizon are hidden

const cv::Scalar ink(30, 30, 30);
const cv::Scalar white(255, 255, 255);

cv::Scalar robot_bgr(uint32_t robot_id) {
  const auto rgb = robot_colour_rgb(robot_id);
  return {static_cast<double>(rgb[2]), static_cast<double>(rgb[1]), static_cast<double>(rgb[0])};
}

struct Bounds {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x, min_z = min_x;
  double max_x = -min_x, max_y = -min_x, max_z = -min_x;
  void add(double x, double y, double z) {
    min_x = std::min(min_x, x), max_x = std::max(max_x, x);
    min_y = std::min(min_y, y), max_y = std::max(max_y, y);
    min_z = std::min(min_z, z), max_z = std::max(max_z, z);
  }
  bool empty() const { return !(min_x <= max_x); }
};

// The x-y bounds of the triangles' vertices (vertices no triangle uses are left out) and of
// the path samples.
Bounds data_bounds(const io::TriangleMesh& mesh, const std::vector<PathSample>& paths) {
  Bounds b;
  for (const auto& t : mesh.triangles)
    for (const uint32_t i : t)
      if (i < mesh.vertices.size()) b.add(mesh.vertices[i].x, mesh.vertices[i].y, 0);
  for (const PathSample& p : paths) b.add(p.x_m, p.y_m, 0);
  return b;
}

std::string check_inputs(const io::TriangleMesh& mesh, const std::vector<PathSample>& paths,
                         const PlotOptions& options) {
  if (options.long_side_px < 200 || options.long_side_px > 20000)
    return "long_side_px " + std::to_string(options.long_side_px) + " not in [200, 20000]";
  for (size_t i = 0; i < mesh.triangles.size(); ++i)
    for (const uint32_t v : mesh.triangles[i]) {
      if (v >= mesh.vertices.size())
        return "mesh triangle " + std::to_string(i) + ": vertex index " + std::to_string(v) +
               " out of range (" + std::to_string(mesh.vertices.size()) + " vertices)";
      const msg::Vec3& p = mesh.vertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        return "mesh vertex " + std::to_string(v) + " is not finite";
      if (std::abs(p.x) > kMaxCoordinateM || std::abs(p.y) > kMaxCoordinateM ||
          std::abs(p.z) > kMaxCoordinateM)
        return "mesh vertex " + std::to_string(v) + " lies beyond ±1e7 m";
    }
  for (size_t i = 0; i < paths.size(); ++i) {
    if (!std::isfinite(paths[i].t_s) || !std::isfinite(paths[i].x_m) ||
        !std::isfinite(paths[i].y_m))
      return "path sample " + std::to_string(i) + " (robot " + std::to_string(paths[i].robot_id) +
             ") is not finite";
    if (std::abs(paths[i].x_m) > kMaxCoordinateM || std::abs(paths[i].y_m) > kMaxCoordinateM)
      return "path sample " + std::to_string(i) + " (robot " + std::to_string(paths[i].robot_id) +
             ") lies beyond ±1e7 m";
  }
  return {};
}

// Each robot's samples in time order.
std::map<uint32_t, std::vector<PathSample>> by_robot(const std::vector<PathSample>& paths) {
  std::map<uint32_t, std::vector<PathSample>> robots;
  for (const PathSample& p : paths) robots[p.robot_id].push_back(p);
  for (auto& [id, samples] : robots)
    std::stable_sort(samples.begin(), samples.end(),
                     [](const PathSample& a, const PathSample& b) { return a.t_s < b.t_s; });
  return robots;
}

void draw_mesh(cv::Mat& img, const io::TriangleMesh& mesh, const TopViewGeometry& g, double min_z,
               double max_z) {
  // lowest triangles first, so that what is higher covers what lies below it
  std::vector<double> mean_z(mesh.triangles.size());
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    mean_z[i] = (mesh.vertices[t[0]].z + mesh.vertices[t[1]].z + mesh.vertices[t[2]].z) / 3;
  }
  std::vector<size_t> order(mesh.triangles.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return mean_z[a] < mean_z[b]; });
  const double span = max_z - min_z;
  for (const size_t i : order) {
    // a face turned down (a ceiling's underside) is seen from below, not from above: it
    // would hide the floor and everything on it. Reconstructions are wound counter-clockwise
    // seen from outside (core/tsdf/mesher.hpp), so the face normal tells.
    const auto& t = mesh.triangles[i];
    const msg::Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
    const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
    const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    if (nz < -kDownFacing * std::sqrt(nx * nx + ny * ny + nz * nz)) continue;
    const double s = span > 0 ? (mean_z[i] - min_z) / span : 0;
    const double grey = kLowGrey + s * (kHighGrey - kLowGrey);
    std::array<cv::Point, 3> corners;
    for (int k = 0; k < 3; ++k) {
      const msg::Vec3& v = mesh.vertices[mesh.triangles[i][k]];
      const auto px = g.to_pixel(v.x, v.y);
      corners[k] = canvas::fixed({px[0], px[1]});
    }
    cv::fillConvexPoly(img, corners.data(), 3, cv::Scalar(grey, grey, grey), cv::LINE_8,
                       canvas::kShift);
  }
}

void draw_paths(cv::Mat& img, const std::map<uint32_t, std::vector<PathSample>>& robots,
                const TopViewGeometry& g, const canvas::Style& st) {
  const int line = st.thickness(3);
  const int halo = line + 2 * st.thickness(1.5);
  const double marker = 7 * st.unit;
  for (const auto& [id, samples] : robots) {
    std::vector<cv::Point> pts;
    pts.reserve(samples.size());
    for (const PathSample& p : samples) {
      const auto px = g.to_pixel(p.x_m, p.y_m);
      pts.push_back(canvas::fixed({px[0], px[1]}));
    }
    cv::polylines(img, pts, false, white, halo, cv::LINE_AA, canvas::kShift);
    cv::polylines(img, pts, false, robot_bgr(id), line, cv::LINE_AA, canvas::kShift);
  }
  // markers above every line: start circles, end squares, each outlined in ink
  for (const auto& [id, samples] : robots) {
    const auto start = g.to_pixel(samples.front().x_m, samples.front().y_m);
    const auto end = g.to_pixel(samples.back().x_m, samples.back().y_m);
    const cv::Point s = canvas::fixed({start[0], start[1]});
    const int r = static_cast<int>(std::lround(marker * (1 << canvas::kShift)));
    cv::circle(img, s, r, robot_bgr(id), cv::FILLED, cv::LINE_AA, canvas::kShift);
    cv::circle(img, s, r, ink, st.thickness(1.5), cv::LINE_AA, canvas::kShift);
    const cv::Point a = canvas::fixed({end[0] - marker, end[1] - marker});
    const cv::Point b = canvas::fixed({end[0] + marker, end[1] + marker});
    cv::rectangle(img, a, b, robot_bgr(id), cv::FILLED, cv::LINE_AA, canvas::kShift);
    cv::rectangle(img, a, b, ink, st.thickness(1.5), cv::LINE_AA, canvas::kShift);
  }
}

// The right-hand column: robots, markers, height ramp.
void draw_legend(cv::Mat& img, const std::map<uint32_t, std::vector<PathSample>>& robots,
                 const Bounds& z, bool has_mesh, const canvas::Style& st) {
  const double x0 = img.cols - (kRightColumn - 20) * st.unit;
  const double row = 28 * st.unit;
  const double label = st.font(0.55);
  const int thin = st.thickness(1);
  double y = (kTitleBand + 20) * st.unit;
  canvas::text(img, "robots", {x0, y}, st.font(0.6), ink, st.thickness(1.6));
  y += row;
  const double bottom_reserve = (has_mesh ? 300 : 90) * st.unit;
  size_t shown = 0;
  for (const auto& [id, samples] : robots) {
    if (y > img.rows - bottom_reserve && shown + 1 < robots.size()) {
      canvas::text(img, std::to_string(robots.size() - shown) + " more robots", {x0, y}, label, ink,
                   thin);
      y += row;
      break;
    }
    const double mid = y - 6 * st.unit;
    cv::line(img, canvas::fixed({x0, mid}), canvas::fixed({x0 + 36 * st.unit, mid}), robot_bgr(id),
             st.thickness(4), cv::LINE_AA, canvas::kShift);
    canvas::text(img, "robot " + std::to_string(id), {x0 + 46 * st.unit, y}, label, ink, thin);
    y += row;
    ++shown;
  }
  if (robots.empty()) {
    canvas::text(img, "(no paths)", {x0, y}, label, ink, thin);
    y += row;
  }
  // marker key
  y += 0.4 * row;
  const double m = 7 * st.unit;
  const cv::Scalar key(150, 150, 150);
  cv::circle(img, canvas::fixed({x0 + 18 * st.unit, y - m}),
             static_cast<int>(std::lround(m * (1 << canvas::kShift))), key, cv::FILLED, cv::LINE_AA,
             canvas::kShift);
  canvas::text(img, "start", {x0 + 46 * st.unit, y}, label, ink, thin);
  y += row;
  cv::rectangle(img, canvas::fixed({x0 + 18 * st.unit - m, y - 2 * m}),
                canvas::fixed({x0 + 18 * st.unit + m, y}), key, cv::FILLED, cv::LINE_AA,
                canvas::kShift);
  canvas::text(img, "end", {x0 + 46 * st.unit, y}, label, ink, thin);
  y += row;
  if (!has_mesh) return;
  // white within the mesh (box tops): surface no camera saw, above the cameras, not a hole
  cv::rectangle(img, canvas::fixed({x0 + 18 * st.unit - m, y - 2 * m}),
                canvas::fixed({x0 + 18 * st.unit + m, y}), ink, thin, cv::LINE_AA, canvas::kShift);
  canvas::text(img, "not seen by", {x0 + 46 * st.unit, y}, label, ink, thin);
  y += 0.8 * row;
  canvas::text(img, "any camera", {x0 + 46 * st.unit, y}, label, ink, thin);
  y += row;
  // height ramp: highest at the top
  y += 0.6 * row;
  canvas::text(img, "mesh height (m)", {x0, y}, st.font(0.55), ink, st.thickness(1.4));
  y += 0.6 * row;
  const double bar_h = std::min(150 * st.unit, img.rows - y - (kBottomBand + 10) * st.unit);
  if (bar_h < 30 * st.unit) return;
  const int bar_w = static_cast<int>(22 * st.unit);
  for (int r = 0; r < static_cast<int>(bar_h); ++r) {
    const double s = 1 - r / std::max(1.0, bar_h - 1);
    const double grey = kLowGrey + s * (kHighGrey - kLowGrey);
    cv::line(img, cv::Point(static_cast<int>(x0), static_cast<int>(y) + r),
             cv::Point(static_cast<int>(x0) + bar_w, static_cast<int>(y) + r),
             cv::Scalar(grey, grey, grey), 1);
  }
  cv::rectangle(img, cv::Point(static_cast<int>(x0), static_cast<int>(y)),
                cv::Point(static_cast<int>(x0) + bar_w, static_cast<int>(y + bar_h)), ink, thin);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", z.max_z);
  canvas::text(img, buf, {x0 + bar_w + 8 * st.unit, y + 10 * st.unit}, label, ink, thin);
  std::snprintf(buf, sizeof buf, "%.2f", z.min_z);
  canvas::text(img, buf, {x0 + bar_w + 8 * st.unit, y + bar_h}, label, ink, thin);
}

// A scale bar of a round length (about a fifth of the plot's width) and the axis directions.
void draw_scale(cv::Mat& img, const TopViewGeometry& g, const canvas::Style& st) {
  const double plot_w_px = img.cols - (kLeftMargin + kRightColumn) * st.unit;
  const double length_m = canvas::nice_floor(0.2 * plot_w_px / g.px_per_m);
  const double length_px = length_m * g.px_per_m;
  const double x = kLeftMargin * st.unit;
  const double y = img.rows - 22 * st.unit;
  const double tick = 6 * st.unit;
  const int t = st.thickness(2.5);
  cv::line(img, canvas::fixed({x, y}), canvas::fixed({x + length_px, y}), ink, t, cv::LINE_AA,
           canvas::kShift);
  for (const double end : {x, x + length_px})
    cv::line(img, canvas::fixed({end, y - tick}), canvas::fixed({end, y + tick}), ink, t,
             cv::LINE_AA, canvas::kShift);
  char buf[32];
  std::snprintf(buf, sizeof buf, length_m >= 1 ? "%.0f m" : "%g m", length_m);
  canvas::text(img, buf, {x + length_px + 12 * st.unit, y + 7 * st.unit}, st.font(0.6), ink,
               st.thickness(1.4));
  // axes: x right, y up
  const double ax = x + length_px + 130 * st.unit;
  const double arrow = 34 * st.unit;
  cv::arrowedLine(img, canvas::fixed({ax, y + tick}), canvas::fixed({ax + arrow, y + tick}), ink,
                  st.thickness(1.5), cv::LINE_AA, canvas::kShift, 0.25);
  cv::arrowedLine(img, canvas::fixed({ax, y + tick}), canvas::fixed({ax, y + tick - arrow}), ink,
                  st.thickness(1.5), cv::LINE_AA, canvas::kShift, 0.25);
  canvas::text(img, "x", {ax + arrow + 5 * st.unit, y + tick + 5 * st.unit}, st.font(0.5), ink,
               st.thickness(1));
  canvas::text(img, "y", {ax - 4 * st.unit, y + tick - arrow - 6 * st.unit}, st.font(0.5), ink,
               st.thickness(1));
}

}  // namespace

std::array<uint8_t, 3> robot_colour_rgb(uint32_t robot_id) {
  // Tableau 10 without its grey, which the mesh uses
  static constexpr std::array<std::array<uint8_t, 3>, 9> kPalette = {{{31, 119, 180},
                                                                      {255, 127, 14},
                                                                      {44, 160, 44},
                                                                      {214, 39, 40},
                                                                      {148, 103, 189},
                                                                      {140, 86, 75},
                                                                      {227, 119, 194},
                                                                      {188, 189, 34},
                                                                      {23, 190, 207}}};
  return kPalette[(static_cast<uint64_t>(robot_id) + kPalette.size() - 1) % kPalette.size()];
}

TopViewGeometry top_view_geometry(const io::TriangleMesh& mesh,
                                  const std::vector<PathSample>& paths,
                                  const PlotOptions& options) {
  const int long_side = options.long_side_px;
  const double unit = long_side / 1000.0;
  Bounds b = data_bounds(mesh, paths);
  if (b.empty()) b.add(0, 0, 0);
  // pad the data, widen the narrow side to the minimum aspect and the minimum extent
  double cx = (b.min_x + b.max_x) / 2, cy = (b.min_y + b.max_y) / 2;
  double w = std::max(kMinExtentM, (b.max_x - b.min_x) * (1 + 2 * kDataPadding));
  double h = std::max(kMinExtentM, (b.max_y - b.min_y) * (1 + 2 * kDataPadding));
  w = std::max(w, kMinAspect * h);
  h = std::max(h, kMinAspect * w);

  TopViewGeometry g;
  const int side_px = static_cast<int>(std::lround((kLeftMargin + kRightColumn) * unit));
  const int band_px = static_cast<int>(std::lround((kTitleBand + kBottomBand) * unit));
  // the wide case first: the width is the long side; else the height is
  const int plot_w = long_side - side_px;
  const int plot_h_wide = static_cast<int>(std::ceil(plot_w * h / w - 1e-9));
  if (band_px + plot_h_wide <= long_side) {
    g.width_px = long_side;
    g.height_px = band_px + plot_h_wide;
    g.px_per_m = plot_w / w;
  } else {
    const int plot_h = long_side - band_px;
    g.height_px = long_side;
    g.width_px = side_px + static_cast<int>(std::ceil(plot_h * w / h - 1e-9));
    g.px_per_m = plot_h / h;
  }
  g.x0_m = cx - w / 2;
  g.y0_m = cy - h / 2;
  g.col0_px = std::round(kLeftMargin * unit);
  g.row0_px = std::round(kTitleBand * unit) + h * g.px_per_m;
  return g;
}

Result<void, std::string> write_top_view_png(const io::TriangleMesh& mesh,
                                             const std::vector<PathSample>& paths,
                                             const std::string& out_png,
                                             const PlotOptions& options) {
  if (std::string e = check_inputs(mesh, paths, options); !e.empty())
    return make_unexpected("top view '" + out_png + "': " + e);
  const std::string title =
      options.title.empty() ? "Top view: reconstruction and robot paths" : options.title;
  if (mesh.triangles.empty() && paths.empty()) {
    const int l = options.long_side_px;
    return canvas::write_png(
        canvas::no_data(l, l * 3 / 4, title, "no mesh triangles and no path samples"), out_png);
  }
  const TopViewGeometry g = top_view_geometry(mesh, paths, options);
  const canvas::Style st{.unit = options.long_side_px / 1000.0};
  cv::Mat img(g.height_px, g.width_px, CV_8UC3, white);

  Bounds z;
  for (const auto& t : mesh.triangles)
    for (const uint32_t i : t) z.add(0, 0, mesh.vertices[i].z);
  draw_mesh(img, mesh, g, z.min_z, z.max_z);
  const auto robots = by_robot(paths);
  draw_paths(img, robots, g, st);

  // frame of the plot area
  const double plot_w = g.width_px - (kLeftMargin + kRightColumn) * st.unit;
  cv::rectangle(img, canvas::fixed({g.col0_px, kTitleBand * st.unit}),
                canvas::fixed({g.col0_px + plot_w, g.row0_px}), cv::Scalar(180, 180, 180),
                st.thickness(1), cv::LINE_AA, canvas::kShift);
  // the title, shrunk to fit, and a note at the right where it fits beside it
  const double room = g.width_px - (kLeftMargin + 20) * st.unit;
  const double title_font = canvas::fit_font(title, st.font(0.75), st.thickness(2), room);
  canvas::text(img, title, {kLeftMargin * st.unit, 38 * st.unit}, title_font, ink, st.thickness(2));
  char note[96];
  std::snprintf(note, sizeof note, "%zu triangles, %zu robot%s%s", mesh.triangles.size(),
                robots.size(), robots.size() == 1 ? "" : "s",
                mesh.triangles.empty() ? " (no mesh)" : "");
  if (canvas::text_size(title, title_font, st.thickness(2)).width +
          canvas::text_size(note, st.font(0.5), st.thickness(1)).width + 30 * st.unit <=
      room)
    canvas::text(img, note, {g.width_px - 20 * st.unit, 38 * st.unit}, st.font(0.5),
                 cv::Scalar(90, 90, 90), st.thickness(1), Align::kRight);
  draw_legend(img, robots, z, !mesh.triangles.empty(), st);
  draw_scale(img, g, st);
  return canvas::write_png(img, out_png);
}

}  // namespace scancrew::report
