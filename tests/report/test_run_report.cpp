// The mission run directory's files, pictures and report: CSV round trips and reader errors,
// a top view and a coverage plot read back with OpenCV, and report.html of synthetic runs.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "report/plots.hpp"
#include "report/run_files.hpp"
#include "report/run_report.hpp"

namespace scancrew::report {
namespace {

namespace fs = std::filesystem;

// A fresh folder under the system's temporary folder, removed with its contents at the end.
class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    path_ = fs::temp_directory_path() / ("scancrew_test_run_report_" + std::to_string(getpid()) +
                                         "_" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A 10 m x 6 m floor at z = 0 with a 2 m x 2 m block top at z = 2 over (4..6, 2..4).
io::TriangleMesh floor_and_block() {
  io::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {10, 0, 0}, {10, 6, 0}, {0, 6, 0},
                   {4, 2, 2}, {6, 2, 2},  {6, 4, 2},  {4, 4, 2}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  return mesh;
}

std::string ascii_ply(const io::TriangleMesh& mesh) {
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\nelement vertex " << mesh.vertices.size()
    << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
    << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : mesh.vertices) s << v.x << " " << v.y << " " << v.z << "\n";
  for (const auto& t : mesh.triangles) s << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return s.str();
}

// Robot 1 along y = 1 and robot 2 along y = 5, from x = 1 to x = 9, samples 0.5 m apart,
// interleaved in time as the mission monitor writes them.
std::vector<PathSample> two_paths() {
  std::vector<PathSample> paths;
  for (int i = 0; i <= 16; ++i)
    for (const uint32_t id : {1U, 2U})
      paths.push_back({.t_s = 0.5 * i,
                       .robot_id = id,
                       .x_m = 1 + 0.5 * i,
                       .y_m = id == 1 ? 1.0 : 5.0,
                       .z_m = 0.2,
                       .yaw_rad = 0});
  return paths;
}

std::vector<CoverageSample> two_coverages() {
  std::vector<CoverageSample> samples;
  for (int i = 0; i <= 20; ++i)
    for (const uint32_t id : {1U, 2U})
      samples.push_back({.t_s = 10.0 * i,
                         .robot_id = id,
                         .coverage = std::min(1.0, 0.06 * i * (id == 1 ? 1.0 : 0.8)),
                         .ises_left = static_cast<uint64_t>(400 - 20 * i)});
  return samples;
}

// Whether some pixel within `radius` of (col, row) has the colour (RGB) within `tolerance`.
bool has_colour_near(const cv::Mat& bgr, std::array<double, 2> px, std::array<uint8_t, 3> rgb,
                     int radius = 1, int tolerance = 3) {
  const int c0 = static_cast<int>(std::lround(px[0])), r0 = static_cast<int>(std::lround(px[1]));
  for (int r = r0 - radius; r <= r0 + radius; ++r)
    for (int c = c0 - radius; c <= c0 + radius; ++c) {
      if (r < 0 || c < 0 || r >= bgr.rows || c >= bgr.cols) continue;
      const auto p = bgr.at<cv::Vec3b>(r, c);
      if (std::abs(p[2] - rgb[0]) <= tolerance && std::abs(p[1] - rgb[1]) <= tolerance &&
          std::abs(p[0] - rgb[2]) <= tolerance)
        return true;
    }
  return false;
}

TEST(RunFiles, CsvRoundTripKeepsTheWrittenPrecision) {
  TempDir dir;
  const std::vector<PathSample> paths = {
      {.t_s = 0.0,
       .robot_id = 1,
       .x_m = 1.23456789,
       .y_m = -2.5,
       .z_m = 0.3,
       .yaw_rad = 3.14159265},
      {.t_s = 12.3456,
       .robot_id = 4000000000U,
       .x_m = -1e3,
       .y_m = 7.77777,
       .z_m = 0,
       .yaw_rad = -1},
  };
  const std::vector<CoverageSample> coverage = {
      {.t_s = 1.0005, .robot_id = 2, .coverage = 0.123456789, .ises_left = 18446744073709551615ULL},
      {.t_s = 2.0, .robot_id = 1, .coverage = 1.0, .ises_left = 0},
  };
  ASSERT_TRUE(write_paths_csv(dir.file("paths.csv"), paths));
  ASSERT_TRUE(write_coverage_csv(dir.file("coverage.csv"), coverage));
  EXPECT_EQ(read_text(dir.file("paths.csv")).substr(0, 33), "t_s,robot_id,x_m,y_m,z_m,yaw_rad\n");

  const auto p = read_paths_csv(dir.file("paths.csv"));
  ASSERT_TRUE(p) << p.error();
  ASSERT_EQ(p->size(), paths.size());
  for (size_t i = 0; i < paths.size(); ++i) {
    EXPECT_NEAR((*p)[i].t_s, paths[i].t_s, 0.5e-3);
    EXPECT_EQ((*p)[i].robot_id, paths[i].robot_id);
    EXPECT_NEAR((*p)[i].x_m, paths[i].x_m, 0.5e-4);
    EXPECT_NEAR((*p)[i].y_m, paths[i].y_m, 0.5e-4);
    EXPECT_NEAR((*p)[i].z_m, paths[i].z_m, 0.5e-4);
    EXPECT_NEAR((*p)[i].yaw_rad, paths[i].yaw_rad, 0.5e-4);
  }
  const auto c = read_coverage_csv(dir.file("coverage.csv"));
  ASSERT_TRUE(c) << c.error();
  ASSERT_EQ(c->size(), coverage.size());
  for (size_t i = 0; i < coverage.size(); ++i) {
    EXPECT_NEAR((*c)[i].t_s, coverage[i].t_s, 0.5e-3);
    EXPECT_EQ((*c)[i].robot_id, coverage[i].robot_id);
    EXPECT_NEAR((*c)[i].coverage, coverage[i].coverage, 0.5e-5);
    EXPECT_EQ((*c)[i].ises_left, coverage[i].ises_left);
  }
}

TEST(RunFiles, HeaderOnlyFileHoldsNoSamples) {
  TempDir dir;
  ASSERT_TRUE(write_paths_csv(dir.file("paths.csv"), {}));
  const auto p = read_paths_csv(dir.file("paths.csv"));
  ASSERT_TRUE(p) << p.error();
  EXPECT_TRUE(p->empty());
}

TEST(RunFiles, ReaderRejectsABadHeaderNamingTheFile) {
  TempDir dir;
  write_text(dir.file("paths.csv"), "t,robot_id,x_m,y_m,z_m,yaw_rad\n0,1,0,0,0,0\n");
  const auto p = read_paths_csv(dir.file("paths.csv"));
  ASSERT_FALSE(p);
  EXPECT_NE(p.error().find(dir.file("paths.csv") + ":1"), std::string::npos) << p.error();
  EXPECT_NE(p.error().find("header"), std::string::npos) << p.error();
}

TEST(RunFiles, ReaderNamesTheLineAndFieldOfANonNumber) {
  TempDir dir;
  write_text(dir.file("paths.csv"),
             "t_s,robot_id,x_m,y_m,z_m,yaw_rad\n0,1,0,0,0,0\n0.1,1,abc,0,0,0\n");
  const auto p = read_paths_csv(dir.file("paths.csv"));
  ASSERT_FALSE(p);
  EXPECT_NE(p.error().find(dir.file("paths.csv") + ":3"), std::string::npos) << p.error();
  EXPECT_NE(p.error().find("x_m"), std::string::npos) << p.error();
  EXPECT_NE(p.error().find("abc"), std::string::npos) << p.error();
}

TEST(RunFiles, ReaderRejectsNanNamingTheLine) {
  TempDir dir;
  write_text(dir.file("coverage.csv"),
             "t_s,robot_id,coverage,coverage_reachable,ises_left\n0,1,nan,-1,3\n");
  const auto c = read_coverage_csv(dir.file("coverage.csv"));
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().find(dir.file("coverage.csv") + ":2"), std::string::npos) << c.error();
  EXPECT_NE(c.error().find("field coverage"), std::string::npos) << c.error();
  EXPECT_NE(c.error().find("not finite"), std::string::npos) << c.error();
}

TEST(RunFiles, ReaderRejectsBadFieldsAndCounts) {
  TempDir dir;
  const std::string header = "t_s,robot_id,coverage,coverage_reachable,ises_left\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0,1,0.5,0.6\n", "4 fields, expected 5"},
      {"0,1,0.5,0.6,3,9\n", "6 fields, expected 5"},
      {"0,1.5,0.5,0.6,3\n", "field robot_id"},
      {"0,-1,0.5,0.6,3\n", "field robot_id"},
      {"0,99999999999,0.5,0.6,3\n", "out of range"},
      {"0,1,1.5,0.6,3\n", "not in [0, 1]"},
      {"0,1,0.5,1.6,3\n", "field coverage_reachable"},
      {"0,1,0.5,0.6,-3\n", "field ises_left"},
      {"inf,1,0.5,0.6,3\n", "field t_s"},
      {"0,1,,0.6,3\n", "field coverage"},
      {"0,1,0.5x,0.6,3\n", "field coverage"},
  };
  for (const auto& [line, expected] : cases) {
    write_text(dir.file("coverage.csv"), header + "0,1,0.1,-1,5\n" + line);
    const auto c = read_coverage_csv(dir.file("coverage.csv"));
    ASSERT_FALSE(c) << line;
    EXPECT_NE(c.error().find(":3"), std::string::npos) << c.error();
    EXPECT_NE(c.error().find(expected), std::string::npos) << c.error();
  }
  const auto missing = read_paths_csv(dir.file("no_such.csv"));
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("no_such.csv"), std::string::npos);
  // a device is one endless line: refused before reading (it ran out of memory)
  const auto device = read_coverage_csv("/dev/zero");
  ASSERT_FALSE(device);
  EXPECT_NE(device.error().find("not a regular file"), std::string::npos) << device.error();
}

TEST(RunFiles, WriterNamesAnUnwritableFile) {
  const auto r = write_paths_csv("/nonexistent_scancrew_dir/paths.csv", {});
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("/nonexistent_scancrew_dir/paths.csv"), std::string::npos);
}

TEST(Plots, TopViewDrawsEachPathInItsRobotsColour) {
  TempDir dir;
  const auto mesh = floor_and_block();
  const auto paths = two_paths();
  const PlotOptions options{.long_side_px = 800};
  ASSERT_TRUE(write_top_view_png(mesh, paths, dir.file("top.png"), options));
  const cv::Mat img = cv::imread(dir.file("top.png"), cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  const TopViewGeometry g = top_view_geometry(mesh, paths, options);
  EXPECT_EQ(std::max(img.cols, img.rows), 800);
  EXPECT_EQ(img.cols, g.width_px);
  EXPECT_EQ(img.rows, g.height_px);
  // along each path, away from its start and end markers
  for (const double x : {2.25, 3.0, 4.5, 5.25, 7.0, 8.0}) {
    EXPECT_TRUE(has_colour_near(img, g.to_pixel(x, 1.0), robot_colour_rgb(1))) << "x " << x;
    EXPECT_TRUE(has_colour_near(img, g.to_pixel(x, 5.0), robot_colour_rgb(2))) << "x " << x;
    EXPECT_FALSE(has_colour_near(img, g.to_pixel(x, 5.0), robot_colour_rgb(1), 3, 20));
  }
  // the floor is light grey, the block top darker grey, outside the mesh is white
  const auto floor = img.at<cv::Vec3b>(static_cast<int>(g.to_pixel(2, 3)[1]),
                                       static_cast<int>(g.to_pixel(2, 3)[0]));
  const auto block = img.at<cv::Vec3b>(static_cast<int>(g.to_pixel(5, 3)[1]),
                                       static_cast<int>(g.to_pixel(5, 3)[0]));
  EXPECT_EQ(floor[0], floor[2]);
  EXPECT_EQ(block[0], block[2]);
  EXPECT_LT(floor[0], 255);
  EXPECT_LT(block[0] + 50, floor[0]);
  const auto outside = img.at<cv::Vec3b>(static_cast<int>(g.to_pixel(-0.2, 3)[1]),
                                         static_cast<int>(g.to_pixel(-0.2, 3)[0]));
  EXPECT_EQ(outside, cv::Vec3b(255, 255, 255));
}

TEST(Plots, RobotColoursAreDistinct) {
  for (uint32_t a = 1; a <= 9; ++a)
    for (uint32_t b = a + 1; b <= 9; ++b) EXPECT_NE(robot_colour_rgb(a), robot_colour_rgb(b));
}

TEST(Plots, TallDataKeepsTheLongSide) {
  TempDir dir;
  std::vector<PathSample> tall;
  tall.reserve(10);
  for (int i = 0; i < 10; ++i)
    tall.push_back({.t_s = 1.0 * i, .robot_id = 3, .x_m = 0, .y_m = 5.0 * i});
  ASSERT_TRUE(write_top_view_png({}, tall, dir.file("tall.png"), {.long_side_px = 600}));
  const cv::Mat img = cv::imread(dir.file("tall.png"));
  EXPECT_EQ(img.rows, 600);
  EXPECT_LE(img.cols, 600);
  EXPECT_TRUE(has_colour_near(img,
                              top_view_geometry({}, tall, {.long_side_px = 600}).to_pixel(0, 22.5),
                              robot_colour_rgb(3)));
}

TEST(Plots, EmptyInputsGiveANoDataPicture) {
  TempDir dir;
  ASSERT_TRUE(write_top_view_png({}, {}, dir.file("top.png")));
  ASSERT_TRUE(write_coverage_png({}, dir.file("cov.png")));
  EXPECT_FALSE(cv::imread(dir.file("top.png")).empty());
  EXPECT_FALSE(cv::imread(dir.file("cov.png")).empty());
}

TEST(Plots, SingleSamplesAndFlatMeshesAreDrawn) {
  TempDir dir;
  io::TriangleMesh flat;
  flat.vertices = {{0, 0, 1}, {1, 0, 1}, {0, 0, 1}};  // one degenerate triangle, one height
  flat.triangles = {{0, 1, 2}};
  const std::vector<PathSample> one = {{.t_s = 3, .robot_id = 7, .x_m = 0.5, .y_m = 0}};
  ASSERT_TRUE(write_top_view_png(flat, one, dir.file("top.png")));
  EXPECT_FALSE(cv::imread(dir.file("top.png")).empty());
  const std::vector<CoverageSample> same_time = {{.t_s = 0, .robot_id = 1, .coverage = 0.5},
                                                 {.t_s = 0, .robot_id = 2, .coverage = 1}};
  ASSERT_TRUE(write_coverage_png(same_time, dir.file("cov.png"), {.long_side_px = 200}));
  EXPECT_EQ(cv::imread(dir.file("cov.png")).cols, 200);
}

// Hostile run files (Step 12's review): two times one ulp apart looped the time axis's ticks
// until memory ran out; coordinates at ±1e308 threw cv::Exception out of the report.
TEST(Plots, ExtremeValuesAreDrawnOrRefusedNotHung) {
  TempDir dir;
  const double t = 1e9;
  const std::vector<CoverageSample> ulp = {
      {.t_s = t, .robot_id = 1, .coverage = 0.5},
      {.t_s = std::nextafter(t, 2 * t), .robot_id = 1, .coverage = 0.6}};
  EXPECT_TRUE(write_coverage_png(ulp, dir.file("ulp.png"), {.long_side_px = 300}));
  const std::vector<CoverageSample> huge = {{.t_s = -1e308, .robot_id = 1, .coverage = 0},
                                            {.t_s = 1e308, .robot_id = 1, .coverage = 1}};
  const auto huge_t = write_coverage_png(huge, dir.file("huge_t.png"), {.long_side_px = 300});
  ASSERT_FALSE(huge_t);
  EXPECT_NE(huge_t.error().find("huge_t.png': coverage sample 0 (robot 1): time beyond"),
            std::string::npos)
      << huge_t.error();
  const std::vector<PathSample> far = {{.t_s = 0, .robot_id = 1, .x_m = -1e308, .y_m = 0},
                                       {.t_s = 1, .robot_id = 1, .x_m = 1e308, .y_m = 1e308}};
  const auto top = write_top_view_png(floor_and_block(), far, dir.file("far.png"));
  ASSERT_FALSE(top);
  EXPECT_NE(top.error().find("far.png': path sample 0 (robot 1) lies beyond"), std::string::npos)
      << top.error();
  io::TriangleMesh wide = floor_and_block();
  wide.vertices.push_back({1e308, -1e308, 0});
  wide.triangles.push_back({0, 1, static_cast<uint32_t>(wide.vertices.size() - 1)});
  const auto mesh = write_top_view_png(wide, {}, dir.file("wide.png"));
  ASSERT_FALSE(mesh);
  EXPECT_NE(mesh.error().find("lies beyond ±1e7 m"), std::string::npos) << mesh.error();
}

TEST(Plots, BadInputsAndOutputsAreErrorsNamingThem) {
  TempDir dir;
  const auto bad_dir = write_top_view_png(floor_and_block(), {}, "/nonexistent_scancrew_dir/t.png");
  ASSERT_FALSE(bad_dir);
  EXPECT_NE(bad_dir.error().find("/nonexistent_scancrew_dir/t.png"), std::string::npos);
  const auto not_png = write_coverage_png(two_coverages(), dir.file("cov.jpg"));
  ASSERT_FALSE(not_png);
  EXPECT_NE(not_png.error().find("cov.jpg"), std::string::npos);
  io::TriangleMesh broken = floor_and_block();
  broken.triangles.push_back({0, 1, 99});
  const auto bad_index = write_top_view_png(broken, {}, dir.file("t.png"));
  ASSERT_FALSE(bad_index);
  EXPECT_NE(bad_index.error().find("out of range"), std::string::npos) << bad_index.error();
  const auto too_small =
      write_top_view_png(floor_and_block(), {}, dir.file("t.png"), {.long_side_px = 10});
  ASSERT_FALSE(too_small);
  EXPECT_NE(too_small.error().find("long_side_px"), std::string::npos);
}

TEST(Plots, CoveragePlotHasTheRequestedSizeAndTheRobotsColours) {
  TempDir dir;
  ASSERT_TRUE(write_coverage_png(two_coverages(), dir.file("cov.png"), {.long_side_px = 1000}));
  const cv::Mat img = cv::imread(dir.file("cov.png"));
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 1000);
  EXPECT_EQ(img.rows, 700);
  for (const uint32_t id : {1U, 2U}) {
    int count = 0;
    const auto rgb = robot_colour_rgb(id);
    for (int r = 0; r < img.rows; ++r)
      for (int c = 0; c < img.cols; ++c) {
        const auto& p = img.at<cv::Vec3b>(r, c);
        count += p[2] == rgb[0] && p[1] == rgb[1] && p[0] == rgb[2];
      }
    EXPECT_GT(count, 500) << "robot " << id;
  }
}

constexpr const char* kMetrics = R"({
  "launch": "launch_cfg/<arena>&team.yaml", "scene": "launch_cfg/scenes/test_arena.yaml",
  "architecture": "distributed", "started": "2026-11-21 10:00:00", "completed": true,
  "stop_reason": "complete", "completion_time_s": 180.5, "sim_time_s": 180.5,
  "wall_time_s": 12.3, "real_time_factor": 14.7, "coverage": 0.983, "mean_error_m": 0.012,
  "std_error_m": null, "rmse_m": 0.025, "total_path_length_m": 150.2,
  "data_exchanged_bytes": 123456, "collisions": 0, "replans": 12,
  "contacts": {"robot_robot": 2, "robot_scene": 5},
  "robots": [{"id": 1, "namespace": "r<1>", "kind": "ground", "path_length_m": 76.7,
              "replans": 6, "coverage": 0.98, "goals_reached": 33, "state": "idle"},
             {"id": 2, "namespace": "r2", "kind": "multirotor", "ises_left": 7}],
  "compute_ms": {"r1/tsdf_mapper": {"callbacks": 1200, "total_ms": 3500.0, "p50_ms": 2.1,
                                    "p99_ms": 9.0},
                 "r1/high_level_planner": {"callbacks": 10, "total_ms": 9000.0}}
})";

TEST(RunReport, WritesTheFiguresAndTablesWithEscapedStrings) {
  TempDir dir;
  write_text(dir.file("metrics.json"), kMetrics);
  write_text(dir.file("mesh.ply"), ascii_ply(floor_and_block()));
  ASSERT_TRUE(write_paths_csv(dir.file("paths.csv"), two_paths()));
  ASSERT_TRUE(write_coverage_csv(dir.file("coverage.csv"), two_coverages()));
  const auto r = write_report(dir.path().string());
  ASSERT_TRUE(r) << r.error();
  EXPECT_FALSE(cv::imread(dir.file("top_view.png")).empty());
  EXPECT_FALSE(cv::imread(dir.file("coverage.png")).empty());
  const std::string html = read_text(dir.file("report.html"));
  EXPECT_NE(html.find("<img src=\"coverage.png\""), std::string::npos);
  EXPECT_NE(html.find("<img src=\"top_view.png\""), std::string::npos);
  // strings from the files are escaped
  EXPECT_NE(html.find("&lt;arena&gt;&amp;team.yaml"), std::string::npos);
  EXPECT_EQ(html.find("<arena>"), std::string::npos);
  EXPECT_NE(html.find("r&lt;1&gt;"), std::string::npos);
  // metrics, absent values, the robots' last ISEs, compute times most expensive first
  EXPECT_NE(html.find("98.3"), std::string::npos);
  EXPECT_NE(html.find("2026-11-21 10:00:00"), std::string::npos);
  EXPECT_NE(html.find("123456 B (120.6 KiB)"), std::string::npos);
  EXPECT_NE(html.find("&mdash;"), std::string::npos);
  EXPECT_NE(html.find("Contacts robot-scene</th><td class=\"n\">5</td>"), std::string::npos);
  // ISEs left: robot 1's from its last row of coverage.csv, robot 2's from metrics.json
  EXPECT_NE(html.find("<td class=\"n\">0</td></tr>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"n\">7</td></tr>"), std::string::npos);
  EXPECT_LT(html.find("r1/high_level_planner"), html.find("r1/tsdf_mapper"));
  // links to the files present, text for the absent; the 3D view's scripts inlined (no
  // script from a file), no external links
  EXPECT_NE(html.find("<a href=\"mesh.ply\">"), std::string::npos);
  EXPECT_EQ(html.find("<a href=\"map.bt\">"), std::string::npos);
  EXPECT_NE(html.find("ui.perfetto.dev"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
}

// A robot alone exchanges nothing (said so, not "0 B"); sub-10 µs compute times keep their
// digits; the per-robot files (mesh_r*.ply, map_r*.bt, ises_*.ply) and topics.txt are listed.
TEST(RunReport, OneRobotShortCallbacksAndPerRobotFiles) {
  TempDir dir;
  write_text(dir.file("metrics.json"), R"({"data_exchanged_bytes": 0,
    "robots": [{"id": 1, "namespace": "r1", "kind": "ground"}],
    "compute_ms": {"r1/path_tracker": {"callbacks": 2000, "total_ms": 8.0, "p50_ms": 0.0041,
                                       "p99_ms": 0.012}}})");
  for (const char* name : {"mesh_r1.ply", "map_r1.bt", "ises_r1.ply", "topics.txt"})
    write_text(dir.file(name), "x");
  const auto r = write_report(dir.path().string());
  ASSERT_TRUE(r) << r.error();
  const std::string html = read_text(dir.file("report.html"));
  EXPECT_NE(html.find("one robot: nothing to exchange"), std::string::npos);
  EXPECT_EQ(html.find(">0 B<"), std::string::npos);
  EXPECT_NE(html.find(">0.0041<"), std::string::npos);
  EXPECT_NE(html.find(">0.012<"), std::string::npos);
  EXPECT_NE(html.find(">0.004<"), std::string::npos);  // the mean, 8 ms / 2000
  for (const char* name : {"mesh_r1.ply", "map_r1.bt", "ises_r1.ply", "topics.txt"})
    EXPECT_NE(html.find(std::string("<a href=\"") + name + "\">"), std::string::npos) << name;
}

TEST(RunReport, OnlyMetricsGivesAReportWithNoDataPictures) {
  TempDir dir;
  write_text(dir.file("metrics.json"), R"({"launch": null})");
  const auto r = write_report(dir.path().string());
  ASSERT_TRUE(r) << r.error();
  const std::string html = read_text(dir.file("report.html"));
  EXPECT_NE(html.find("no per-robot metrics"), std::string::npos);
  EXPECT_NE(html.find("no compute times"), std::string::npos);
  EXPECT_FALSE(cv::imread(dir.file("top_view.png")).empty());
}

TEST(RunReport, UnreadableOptionalFileIsANoteNotAnError) {
  TempDir dir;
  write_text(dir.file("metrics.json"), kMetrics);
  write_text(dir.file("paths.csv"), "not,a,header\n");
  ASSERT_TRUE(write_coverage_csv(dir.file("coverage.csv"), two_coverages()));
  const auto r = write_report(dir.path().string());
  ASSERT_TRUE(r) << r.error();
  const std::string html = read_text(dir.file("report.html"));
  EXPECT_NE(html.find("class=\"note\""), std::string::npos);
  EXPECT_NE(html.find("paths.csv:1"), std::string::npos);
}

TEST(RunReport, MissingOrBrokenMetricsIsAnErrorNamingIt) {
  TempDir dir;
  const auto missing = write_report(dir.path().string());
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("metrics.json"), std::string::npos) << missing.error();
  write_text(dir.file("metrics.json"), "{\"launch\": ");
  const auto broken = write_report(dir.path().string());
  ASSERT_FALSE(broken);
  EXPECT_NE(broken.error().find("metrics.json"), std::string::npos) << broken.error();
  const auto no_dir = write_report(dir.file("no_such_run"));
  ASSERT_FALSE(no_dir);
  EXPECT_NE(no_dir.error().find("no_such_run"), std::string::npos);
}

}  // namespace
}  // namespace scancrew::report

namespace scancrew::report {
namespace {

TEST(RunFiles, TimeToCoverageIsTheFirstSampleOfAnyRobotAtTheShare) {
  const std::vector<CoverageSample> samples = {
      {.t_s = 10, .robot_id = 1, .coverage = 0.40, .coverage_reachable = 0.50},
      {.t_s = 10, .robot_id = 2, .coverage = 0.45, .coverage_reachable = 0.55},
      {.t_s = 20, .robot_id = 1, .coverage = 0.80, .coverage_reachable = 0.91},
      {.t_s = 20, .robot_id = 2, .coverage = 0.88, .coverage_reachable = 0.93},
      {.t_s = 30, .robot_id = 1, .coverage = 0.90, .coverage_reachable = 0.96},
  };
  EXPECT_EQ(time_to_coverage(samples, 0.5, false), 20.0);
  EXPECT_EQ(time_to_coverage(samples, 0.5, true), 10.0);
  EXPECT_EQ(time_to_coverage(samples, 0.9, false), 30.0);
  EXPECT_EQ(time_to_coverage(samples, 0.9, true), 20.0);
  EXPECT_EQ(time_to_coverage(samples, 0.95, true), 30.0);
  EXPECT_FALSE(time_to_coverage(samples, 0.95, false));
  // not measured (-1) never reaches a share
  EXPECT_FALSE(time_to_coverage({{.t_s = 1, .robot_id = 1, .coverage = 1.0}}, 0.5, true));
}

}  // namespace
}  // namespace scancrew::report
