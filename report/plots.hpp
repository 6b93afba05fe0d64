#pragma once

// The pictures of a mission report (PNG, drawn with OpenCV inside plots.cpp):
//   - a top view of the reconstruction and of the robots' paths (x right, y up), the mesh's
//     triangles projected on x-y and filled with a grey ramp by height (lowest drawn first),
//     each robot's path in its own colour with a start circle and an end square, a legend
//     (which says that white within the mesh, as on box tops, is surface no camera saw),
//     a scale bar and a height bar;
//   - coverage (%) over time, one line per robot (the first solid, the others dashed, so
//     that coinciding curves all show), with the 90 % and 95 % levels, and the
//     ISEs left per robot on a panel below (the thesis' completion criterion, 5.4).
// Empty inputs give a picture that says "no data"; errors name the output file.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/io/triangle_mesh.hpp"
#include "core/result.hpp"
#include "report/run_files.hpp"

namespace scancrew::report {

struct PlotOptions {
  int long_side_px = 1000;  // the image's longer side; the other follows from the data
  std::string title;        // "" = a default title; ASCII only (OpenCV's Hershey fonts)
};

// The colour of a robot in every picture (and in the report): a qualitative palette
// (Tableau 10 without its grey), robot id 1 the first colour. Red, green, blue, 0..255.
std::array<uint8_t, 3> robot_colour_rgb(uint32_t robot_id);

// Where the top view puts the world: the image size and the world -> pixel map (pixel
// column right, row down; world x right, y up). Computed from the union of the mesh's and
// the paths' x-y bounds, as write_top_view_png draws them.
struct TopViewGeometry {
  int width_px = 0, height_px = 0;
  double px_per_m = 1;
  double x0_m = 0, y0_m = 0;  // the world point at pixel (col0_px, row0_px)
  double col0_px = 0, row0_px = 0;

  std::array<double, 2> to_pixel(double x_m, double y_m) const {
    return {col0_px + (x_m - x0_m) * px_per_m, row0_px - (y_m - y0_m) * px_per_m};
  }
};
TopViewGeometry top_view_geometry(const io::TriangleMesh& mesh,
                                  const std::vector<PathSample>& paths,
                                  const PlotOptions& options = {});

// The mesh's faces turned up or sideways, shaded by height (a face turned down, as a
// ceiling's underside, would be seen from below and is left out; reconstructions are wound
// counter-clockwise seen from outside); each robot's path on top.
// Errors: options out of range (long side below 200 px or above 20000 px), a triangle
// index out of range, a non-finite coordinate, an output path that cannot be written.
Result<void, std::string> write_top_view_png(const io::TriangleMesh& mesh,
                                             const std::vector<PathSample>& paths,
                                             const std::string& out_png,
                                             const PlotOptions& options = {});

// Image of long_side_px x 0.7 long_side_px. Errors: as write_top_view_png.
Result<void, std::string> write_coverage_png(const std::vector<CoverageSample>& samples,
                                             const std::string& out_png,
                                             const PlotOptions& options = {});

}  // namespace scancrew::report
