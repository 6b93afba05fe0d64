// The report's 3D view and per-robot contribution (report/scene_view.hpp): the coloured PLY
// reader, the owners' surface, the scene JSON (decimation, ISE classes, HTML safety), the
// report's sections, and the coverage plot's dashes for coinciding robots.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/ply.hpp"
#include "core/tsdf/ply_mesh.hpp"
#include "report/coloured_ply.hpp"
#include "report/plots.hpp"
#include "report/run_report.hpp"
#include "report/scene_view.hpp"

namespace scancrew::report {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    path_ = fs::temp_directory_path() / ("scancrew_test_scene_view_" + std::to_string(getpid()) +
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

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Two floor triangles: (0,0)-(1,0)-(0,1), 0.5 m², robot 1's; (2,0)-(4,0)-(2,2), 2 m², robot 2's.
ColouredPly two_owners() {
  ColouredPly m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {4, 0, 0}, {2, 2, 0}};
  const auto a = tsdf::owner_colour(1), b = tsdf::owner_colour(2);
  m.colours = {a, a, a, b, b, b};
  m.triangles = {{0, 1, 2}, {3, 4, 5}};
  return m;
}

Result<void, std::string> write_mesh(const std::string& path, const ColouredPly& m) {
  std::vector<std::array<float, 3>> normals(m.positions.size(), {0, 0, 1});
  return io::write_ply(path, {.positions = io::flat(m.positions),
                              .normals = io::flat(normals),
                              .colours = io::flat(m.colours),
                              .triangles = io::flat(m.triangles),
                              .mesh = true});
}

// An n x n grid of unit squares on the floor, two triangles each.
ColouredPly grid(int n) {
  ColouredPly m;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      m.positions.push_back({static_cast<float>(x) * 0.1f, static_cast<float>(y) * 0.1f, 0});
  const auto at = [n](int x, int y) { return static_cast<uint32_t>(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      m.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
      m.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
    }
  return m;
}

Json parse_scene(const std::string& json) {
  std::string text = json;
  for (size_t at = text.find("<\\/"); at != std::string::npos; at = text.find("<\\/", at))
    text.replace(at, 3, "</");
  return Json::parse(text);
}

TEST(ColouredPly, ReadsBackWhatWritePlyWroteWithItsColours) {
  TempDir dir;
  const ColouredPly m = two_owners();
  ASSERT_TRUE(write_mesh(dir.file("m.ply"), m));
  const auto r = read_coloured_ply(dir.file("m.ply"));
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->positions, m.positions);
  EXPECT_EQ(r->colours, m.colours);
  EXPECT_EQ(r->triangles, m.triangles);
}

TEST(ColouredPly, ErrorsNameTheFileAndTheCause) {
  TempDir dir;
  std::ofstream(dir.file("ascii.ply")) << "ply\nformat ascii 1.0\nelement vertex 1\n"
                                          "property float x\nend_header\n0\n";
  const auto ascii = read_coloured_ply(dir.file("ascii.ply"));
  ASSERT_FALSE(ascii);
  EXPECT_NE(ascii.error().find("ascii.ply"), std::string::npos);
  EXPECT_NE(ascii.error().find("ascii"), std::string::npos);
  ASSERT_TRUE(write_mesh(dir.file("m.ply"), two_owners()));
  const std::string whole = read_text(dir.file("m.ply"));
  std::ofstream(dir.file("cut.ply"), std::ios::binary) << whole.substr(0, whole.size() - 5);
  const auto cut = read_coloured_ply(dir.file("cut.ply"));
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().find("ends at face 1"), std::string::npos) << cut.error();
  EXPECT_FALSE(read_coloured_ply(dir.file("absent.ply")));
}

TEST(SceneView, SurfaceOfEachRobotIsTheAreaInItsOwnerColour) {
  const ColouredPly m = two_owners();
  const auto area = surface_by_robot_m2(m, {{.id = 1}, {.id = 2}, {.id = 3}});
  ASSERT_EQ(area.size(), 3u);
  EXPECT_NEAR(area.at(1), 0.5, 1e-9);
  EXPECT_NEAR(area.at(2), 2.0, 1e-9);
  EXPECT_EQ(area.at(3), 0.0);
  EXPECT_NEAR(mesh_area_m2(m), 2.5, 1e-9);
  ColouredPly grey = m;
  grey.colours.clear();
  EXPECT_TRUE(surface_by_robot_m2(grey, {{.id = 1}, {.id = 2}}).empty());
}

TEST(SceneView, MeshOverTheCapIsDecimatedUnderItAndSaysSo) {
  const ColouredPly m = grid(100);  // 20000 triangles
  const SceneJson small = scene_json(m, {}, {}, {}, {.max_triangles = 5000});
  EXPECT_EQ(small.triangles_in_file, 20000u);
  EXPECT_LE(small.triangles_shown, 5000u);
  EXPECT_GT(small.triangles_shown, 1000u);
  const Json j = parse_scene(small.json);
  EXPECT_EQ(j["mesh"]["triangles"].get<size_t>(), small.triangles_shown);
  EXPECT_NE(j["mesh"]["note"].get<std::string>().find("decimated"), std::string::npos);
  // base64 of 12 bytes a triangle
  EXPECT_EQ(j["mesh"]["indices"].get<std::string>().size(),
            (12 * small.triangles_shown + 2) / 3 * 4);
  const SceneJson whole = scene_json(m, {}, {}, {});
  EXPECT_EQ(whole.triangles_shown, 20000u);
  EXPECT_EQ(parse_scene(whole.json)["mesh"]["note"], "");
}

TEST(SceneView, PathsIseClassesAndOwnersAreInTheScene) {
  std::vector<PathSample> paths;
  for (int i = 0; i <= 100; ++i) {  // robot 1 moves 10 cm a sample; robot 2 stands still
    paths.push_back({.t_s = 0.1 * i, .robot_id = 1, .x_m = 0.1 * i});
    paths.push_back({.t_s = 0.1 * i, .robot_id = 2, .x_m = 5});
  }
  ColouredPly ises;
  ises.positions = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}, {3, 0, 1}};
  ises.colours = {{40, 200, 40}, {220, 40, 40}, {220, 40, 40}, {40, 80, 230}};
  const SceneJson s = scene_json(two_owners(), paths, {{.id = 1, .name = "r1"}, {.id = 2}},
                                 {ises, ises}, {.path_step_m = 0.25});
  const Json j = parse_scene(s.json);
  ASSERT_EQ(j["paths"].size(), 2u);
  // every third sample (30 cm >= 25 cm) from 0 to 9.9 m, and its last
  EXPECT_EQ(j["paths"][0]["points"].size(), 3u * 35);
  EXPECT_EQ(j["paths"][1]["points"].size(), 3u * 2);  // its first and its last
  // the same points in two files count once
  EXPECT_EQ(j["ises"]["inspectable"].size(), 3u);
  EXPECT_EQ(j["ises"]["c_rem"].size(), 6u);
  EXPECT_EQ(j["ises"]["viewpoints"].size(), 3u);
  EXPECT_EQ(j["robots"][0]["name"], "r1");
  EXPECT_EQ(j["robots"][1]["name"], "r2");
  EXPECT_EQ(j["robots"][0]["colour"].get<std::string>().size(), 7u);
  EXPECT_EQ(j["mesh"]["owners"], "AQEBAgIC");  // bytes 1 1 1 2 2 2
}

TEST(SceneView, SceneJsonCannotCloseItsScriptElement) {
  const SceneJson s =
      scene_json({}, {{.robot_id = 1}}, {{.id = 1, .name = "</script><script>alert(1)"}}, {});
  EXPECT_EQ(s.json.find("</"), std::string::npos);
  EXPECT_EQ(parse_scene(s.json)["robots"][0]["name"], "</script><script>alert(1)");
}

TEST(RunReport, HasThe3DViewAndWhatEachRobotContributed) {
  TempDir dir;
  std::ofstream(dir.file("metrics.json"))
      << R"({"robots": [{"id": 1, "namespace": "r1", "patch_bytes_sent": 2048},
                        {"id": 2, "namespace": "r2", "patch_bytes_sent": 10}]})";
  ASSERT_TRUE(write_mesh(dir.file("mesh.ply"), two_owners()));
  ASSERT_TRUE(write_paths_csv(dir.file("paths.csv"),
                              {{.robot_id = 1}, {.t_s = 1, .robot_id = 1, .x_m = 1}}));
  const auto r = write_report(dir.path().string());
  ASSERT_TRUE(r) << r.error();
  const std::string html = read_text(dir.file("report.html"));
  EXPECT_NE(html.find("<h2>3D view</h2>"), std::string::npos);
  EXPECT_NE(html.find("<script type=\"application/json\" id=\"scancrew-scene\">"),
            std::string::npos);
  // three.js inlined with its licence notice, and nothing else than these two scripts
  EXPECT_NE(html.find("three.js 0."), std::string::npos);
  EXPECT_NE(html.find("The MIT License"), std::string::npos);
  EXPECT_NE(html.find("OrbitControls"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_NE(html.find("no camera saw"), std::string::npos);
  // each robot's surface (m², share) and the data it sent
  EXPECT_NE(html.find("What each robot contributed"), std::string::npos);
  EXPECT_NE(html.find("r1</td><td class=\"n\">0.5</td><td class=\"n\">20.0</td><td "
                      "class=\"n\">2.0 KiB</td>"),
            std::string::npos);
  EXPECT_NE(html.find("r2</td><td class=\"n\">2.0</td><td class=\"n\">80.0</td><td "
                      "class=\"n\">10 B</td>"),
            std::string::npos);
}

// Two robots with the same coverage (a distributed team's shared map): the second is dashed,
// so the first's colour still shows along the curve.
TEST(Plots, CoincidingCoverageCurvesBothShow) {
  TempDir dir;
  std::vector<CoverageSample> samples;
  for (int i = 0; i <= 20; ++i)
    for (const uint32_t id : {1u, 2u})
      samples.push_back({.t_s = 5.0 * i, .robot_id = id, .coverage = 0.05 * i, .ises_left = 10});
  ASSERT_TRUE(write_coverage_png(samples, dir.file("c.png")));
  const cv::Mat img = cv::imread(dir.file("c.png"));
  ASSERT_FALSE(img.empty());
  auto count = [&](uint32_t id) {
    const auto rgb = robot_colour_rgb(id);
    int n = 0;
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols * 3 / 4; ++x) {  // left of the legend
        const auto& p = img.at<cv::Vec3b>(y, x);
        n += std::abs(p[2] - rgb[0]) + std::abs(p[1] - rgb[1]) + std::abs(p[0] - rgb[2]) < 30;
      }
    return n;
  };
  EXPECT_GT(count(1), 1000);
  EXPECT_GT(count(2), 1000);
}

}  // namespace
}  // namespace scancrew::report
