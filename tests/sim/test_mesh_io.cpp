// Scene meshes: read with assimp, placed to fit their box, written as textured OBJ, and
// rendered where the scene says (depth to a mesh wall within 1 mm).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/mesh_io.hpp"
#include "tests/sim/sim_fixtures.hpp"

namespace scancrew::sim {
namespace {

namespace fs = std::filesystem;

// An sx x sy x sz box as 12 triangles, its corner at the origin, as OBJ text.
std::string box_obj(double sx, double sy, double sz) {
  std::ostringstream obj;
  for (int k = 0; k < 8; ++k)  // corners 1-4 at z = 0, 5-8 at z = sz, counter-clockwise
    obj << "v " << ((k % 4 == 1 || k % 4 == 2) ? sx : 0) << ' ' << ((k % 4 >= 2) ? sy : 0) << ' '
        << (k >= 4 ? sz : 0) << '\n';
  obj << "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\n"
         "f 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  return obj.str();
}
const std::string kBoxObj = box_obj(2, 1, 0.5);
constexpr double kBoxArea = 2 * (2 * 1 + 2 * 0.5 + 1 * 0.5);

class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() /
        ("scancrew_mesh_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  fs::path dir_;
};

void expect_near(const msg::Vec3& a, double x, double y, double z) {
  EXPECT_NEAR(a.x, x, 1e-9);
  EXPECT_NEAR(a.y, y, 1e-9);
  EXPECT_NEAR(a.z, z, 1e-9);
}

TEST_F(MeshIo, ReadsAnObjAndPlacesItToFitItsBox) {
  auto mesh = load_mesh(write("box.obj", kBoxObj));
  ASSERT_TRUE(mesh) << mesh.error();
  EXPECT_EQ(mesh->triangles.size(), 12u);
  EXPECT_NEAR(mesh->area(), kBoxArea, 1e-9);
  MeshSpec spec;
  spec.fit_m = {4, 4, 4};  // the x extent limits: scale 2
  spec.center_m = {1, 2, 0.5};
  const TriangleMesh placed = place_mesh(*mesh, spec);
  expect_near(placed.min(), -1, 1, 0.5);
  expect_near(placed.max(), 3, 3, 1.5);
  EXPECT_NEAR(placed.area(), 4 * kBoxArea, 1e-9);
}

TEST_F(MeshIo, TheTexturedObjReadsBackAsTheSameSurface) {
  auto mesh = load_mesh(write("box.obj", kBoxObj));
  ASSERT_TRUE(mesh);
  const std::string out = (dir_ / "out.obj").string();
  ASSERT_TRUE(write_textured_obj(*mesh, 0.5, out));
  auto back = load_mesh(out);
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(back->triangles.size(), 12u);
  EXPECT_NEAR(back->area(), kBoxArea, 1e-6);
  expect_near(back->min(), 0, 0, 0);
  expect_near(back->max(), 2, 1, 0.5);
  // every corner has its own texture coordinate: x / 0.5 on the bottom face, etc.
  std::ifstream in(out);
  size_t vt = 0;
  for (std::string line; std::getline(in, line);) vt += line.rfind("vt ", 0) == 0 ? 1 : 0;
  EXPECT_EQ(vt, 36u);
}

TEST_F(MeshIo, BadFilesAreErrorsNamingTheFile) {
  auto missing = load_mesh((dir_ / "none.obj").string());
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("none.obj' does not exist"), std::string::npos) << missing.error();
  auto empty = load_mesh(write("empty.obj", "# nothing here\nv 0 0 0\n"));
  ASSERT_FALSE(empty);
  EXPECT_NE(empty.error().find("empty.obj"), std::string::npos) << empty.error();
  auto flat = load_mesh(write("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  ASSERT_FALSE(flat);
  EXPECT_NE(flat.error().find("flat or degenerate"), std::string::npos) << flat.error();
  // a device or a folder is no mesh (Assimp would read /dev/zero for ever)
  auto device = load_mesh("/dev/zero");
  ASSERT_FALSE(device);
  EXPECT_NE(device.error().find("not a regular file"), std::string::npos) << device.error();
  // a face that names a vertex the file does not have: an error, or (if the importer drops
  // the face itself) a mesh whose every index is in range
  auto beyond = load_mesh(write("beyond.obj",
                                "v 0 0 0\nv 1 0 0\nv 0 1 1\nv 1 1 1\n"
                                "f 1 2 3\nf 2 3 4\nf 1 2 9\n"));
  if (beyond) {
    for (const auto& t : beyond->triangles)
      for (const uint32_t i : t) EXPECT_LT(i, beyond->vertices.size());
  } else {
    EXPECT_NE(beyond.error().find("beyond.obj"), std::string::npos) << beyond.error();
  }
  EXPECT_TRUE(mesh_format_supported(".dae"));
  EXPECT_TRUE(mesh_format_supported(".stl"));
  EXPECT_FALSE(mesh_format_supported(".xyz123"));
}

TEST_F(MeshIo, TheShippedPowerplantFitsTheThesisFootprintOnTheGround) {
  auto scene = load_scene(std::string(SCANCREW_SOURCE_DIR) + "/launch_cfg/scenes/powerplant.yaml");
  ASSERT_TRUE(scene) << scene.error().front();
  ASSERT_EQ(scene->meshes.size(), 1u);
  EXPECT_FALSE(scene->meshes[0].attribution.empty());
  auto meshes = load_scene_meshes(*scene);
  ASSERT_TRUE(meshes) << meshes.error();
  const msg::Vec3 lo = (*meshes)[0].min(), hi = (*meshes)[0].max();
  // it fits 65 x 42 m and touches the box on its limiting side (y: 64.4 x 42 m)
  EXPECT_LE(hi.x - lo.x, 65.0 + 1e-6);
  EXPECT_NEAR(hi.y - lo.y, 42.0, 1e-6);
  EXPECT_GT(hi.x - lo.x, 64.0);
  EXPECT_NEAR(lo.z, 0.0, 1e-9);
  EXPECT_GT((*meshes)[0].triangles.size(), 1000u);
}

TEST_F(MeshIo, AMeshWallRendersWhereTheSceneSaysWithin1mm) {
  // a 0.2 x 8 x 3 m slab, as the wall box of wall_scene()
  write("slab.obj", box_obj(0.2, 8, 3));
  auto scene = parse_scene(R"(
name: mesh_wall
bounds_min_m: [-5, -5, 0]
bounds_max_m: [5, 5, 3]
meshes:
  - {name: slab, file: slab.obj, fit_m: [0.2, 8, 3], center_m: [3.0, 0, 0]}
)",
                           "mesh_wall.yaml", dir_.string());
  ASSERT_TRUE(scene) << scene.error().front();
  auto sim = test::make_sim(*scene, {test::ground_robot("r1", 0, 0)}, true);
  ASSERT_TRUE(sim);
  msg::StereoFrame stereo;
  msg::DepthImage depth;
  ASSERT_TRUE(sim->render_stereo(0, &stereo, &depth));
  const uint32_t w = depth.intrinsics.width, h = depth.intrinsics.height;
  // the camera is at x = 0.25 m; the slab's front face is the plane x = 2.9 m
  double worst = 0;
  for (uint32_t y = 0; y < h / 2; ++y)
    for (uint32_t x = 0; x < w; ++x)
      worst = std::max(worst, std::abs(depth.depth_m[size_t{y} * w + x] - 2.65));
  EXPECT_LT(worst, 1e-3);
  // and it is textured (box-projected texture coordinates): not a flat image
  double mean = 0, var = 0;
  for (uint32_t y = 0; y < h / 2; ++y)
    for (uint32_t x = 0; x < w; ++x) mean += stereo.left[size_t{y} * w + x];
  mean /= static_cast<double>(w) * (h / 2);
  for (uint32_t y = 0; y < h / 2; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const double d = stereo.left[size_t{y} * w + x] - mean;
      var += d * d;
    }
  EXPECT_GT(std::sqrt(var / (static_cast<double>(w) * (h / 2))), 10.0);
}

}  // namespace
}  // namespace scancrew::sim
