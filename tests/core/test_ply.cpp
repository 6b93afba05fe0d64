// PLY meshes written byte by byte here (not by a writer of ours), read back; write_ply's
// bytes checked against the format, and its meshes read back.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/ply.hpp"

namespace scancrew::io {
namespace {

std::string temp_path(const std::string& name) {
  return ::testing::TempDir() + "scancrew_test_ply_" + name;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// the bytes of a value in the given byte order
template <class T>
std::string bytes(T value, bool big_endian = false) {
  auto raw = std::bit_cast<std::array<char, sizeof(T)>>(value);
  if (big_endian != (std::endian::native == std::endian::big)) std::reverse(raw.begin(), raw.end());
  return {raw.begin(), raw.end()};
}

using Triangles = std::vector<std::array<uint32_t, 3>>;

// A unit square (0,0,0) (1,0,0) (1,1,0) (0,1,0), as one triangle and one quad, with normals
// and colours on the vertices and an "edge" element between vertices and faces.
std::string binary_square(size_t cut_bytes = 0) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\ncomment made by hand\n"
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  const float xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const auto& v : xy) {
    for (const float f : {v[0], v[1], 0.0F, 0.0F, 0.0F, 1.0F}) s += bytes(f);
    s += "\x10\x20\x30";
  }
  s += bytes<int32_t>(0) + bytes<int32_t>(1);
  s += bytes<uint8_t>(3) + bytes<int32_t>(0) + bytes<int32_t>(1) + bytes<int32_t>(2);
  s += bytes<uint8_t>(4);
  for (const int32_t i : {0, 1, 2, 3}) s += bytes(i);
  return s.substr(0, s.size() - cut_bytes);
}

TEST(PlyMesh, ReadsABinaryMeshSkippingNormalsColoursAndOtherElements) {
  const auto mesh = read_ply_mesh(write_file("square.ply", binary_square()));
  ASSERT_TRUE(mesh) << mesh.error();
  ASSERT_EQ(mesh->vertices.size(), 4u);
  EXPECT_EQ(mesh->vertices[2].x, 1.0);
  EXPECT_EQ(mesh->vertices[2].y, 1.0);
  EXPECT_EQ(mesh->vertices[3].z, 0.0);
  // the quad is split into a fan around its first vertex
  EXPECT_EQ(mesh->triangles, (Triangles{{0, 1, 2}, {0, 1, 2}, {0, 2, 3}}));
}

TEST(PlyMesh, ReadsAnAsciiMeshWithDoublesAndWindowsLineEnds) {
  const auto path = write_file("ascii.ply",
                               "ply\r\nformat ascii 1.0\r\ncomment ascii\r\n"
                               "element vertex 3\r\nproperty double x\r\nproperty double y\r\n"
                               "property double z\r\nproperty uchar alpha\r\n"
                               "element face 1\r\nproperty list uint uint vertex_index\r\n"
                               "end_header\r\n"
                               "0.125 -2 3e-1 255\r\n1 0 0 255\r\n0 1 0.5 0\r\n3 2 1 0\r\n");
  const auto mesh = read_ply_mesh(path);
  ASSERT_TRUE(mesh) << mesh.error();
  ASSERT_EQ(mesh->vertices.size(), 3u);
  EXPECT_EQ(mesh->vertices[0].x, 0.125);
  EXPECT_EQ(mesh->vertices[0].y, -2.0);
  EXPECT_EQ(mesh->vertices[0].z, 0.3);
  EXPECT_EQ(mesh->triangles, (Triangles{{2, 1, 0}}));
}

TEST(PlyMesh, ReadsABigEndianMesh) {
  std::string s =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\n"
      "property double y\nproperty double z\nelement face 1\n"
      "property list ushort uint vertex_indices\nend_header\n";
  for (const double d : {0.0, 0.0, 0.0, 1.5, 0.0, 0.0, 0.0, 2.5, -1.0}) s += bytes(d, true);
  s += bytes<uint16_t>(3, true) + bytes<uint32_t>(0, true) + bytes<uint32_t>(1, true) +
       bytes<uint32_t>(2, true);
  const auto mesh = read_ply_mesh(write_file("big.ply", s));
  ASSERT_TRUE(mesh) << mesh.error();
  EXPECT_EQ(mesh->vertices[1].x, 1.5);
  EXPECT_EQ(mesh->vertices[2].y, 2.5);
  EXPECT_EQ(mesh->vertices[2].z, -1.0);
  EXPECT_EQ(mesh->triangles, (Triangles{{0, 1, 2}}));
}

TEST(PlyMesh, AFaceElementOfNoFacesIsAnEmptyMesh) {
  const auto mesh = read_ply_mesh(write_file(
      "empty.ply",
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
      "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"));
  ASSERT_TRUE(mesh) << mesh.error();
  EXPECT_TRUE(mesh->vertices.empty());
  EXPECT_TRUE(mesh->triangles.empty());
}

void expect_error(const std::string& path, const std::string& part) {
  const auto mesh = read_ply_mesh(path);
  ASSERT_FALSE(mesh) << "read " << path;
  EXPECT_NE(mesh.error().find(part), std::string::npos) << mesh.error();
  EXPECT_NE(mesh.error().find(path), std::string::npos) << mesh.error();
}

TEST(PlyMesh, RefusesAMissingFile) {
  expect_error(temp_path("never_written.ply"), "does not exist");
}

TEST(PlyMesh, RefusesAFileThatIsNotAPly) {
  expect_error(write_file("scene.yaml", "name: tiny\nbounds_min_m: [0, 0, 0]\n"), "not a PLY file");
}

TEST(PlyMesh, RefusesATruncatedFileNamingWhereItEnds) {
  expect_error(write_file("cut.ply", binary_square(3)),
               "the data ends early or holds a non-number: element 'face', item 1 of 2");
  const std::string full = binary_square();
  expect_error(write_file("no_body.ply", full.substr(0, full.find("end_header"))), "no end_header");
}

TEST(PlyMesh, RefusesAPointCloud) {
  const std::string path = temp_path("cloud.ply");
  const std::vector<float> xyz = {0, 0, 0, 1, 0, 0}, normals = {0, 0, 1, 0, 0, 1};
  ASSERT_TRUE(write_ply(path, {.positions = xyz, .normals = normals}));
  expect_error(path, "no face element: a point cloud, not a mesh");
}

TEST(PlyMesh, RefusesBadFaces) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  expect_error(write_file("out_of_range.ply", head + "3 0 1 9\n"),
               "face 0 refers to vertex 9, but there are 3 vertices");
  expect_error(write_file("segment.ply", head + "2 0 1\n"), "face 0 has 2 vertices, fewer than 3");
  expect_error(write_file("word.ply", head + "3 0 one 2\n"), "element 'face', item 0 of 1");
  // a corrupt count is refused before anything is allocated for it
  expect_error(write_file("count.ply", head + "4000000000 0 1 2\n"), "element 'face', item 0 of 1");
}

// Counts come from the file, so the work they ask for is bounded by its bytes: an element
// without properties (no data) and a count of 2^62 looped for centuries in a 300-byte file.
TEST(PlyMesh, CountsAreBoundedByTheFilesBytes) {
  const std::string mesh =
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const auto empty = read_ply_mesh(write_file(
      "empty_element.ply", "ply\nformat ascii 1.0\nelement nothing 4611686018427387904\n" + mesh));
  ASSERT_TRUE(empty) << empty.error();
  EXPECT_EQ(empty->triangles.size(), 1U);
  expect_error(write_file("many.ply",
                          "ply\nformat ascii 1.0\nelement vertex 4611686018427387904\n"
                          "property float x\nproperty float y\nproperty float z\n"
                          "element face 0\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0\n"),
               "element 'vertex' counts 4611686018427387904 items, more than the 6 bytes left");
}

TEST(PlyMesh, RefusesAnUnknownFormatOrType) {
  expect_error(write_file("format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"),
               "header line 2 'format binary_middle_endian 1.0': unknown format");
  expect_error(write_file("type.ply",
                          "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\n"
                          "end_header\n"),
               "header line 4 'property float128 x': expected 'property TYPE NAME'");
}

TEST(PlyWrite, HoldsPointsAndNormals) {
  const std::vector<std::array<float, 3>> points = {{1.5f, -2, 3}, {0, 0.25f, 1}},
                                          normals = {{0, 0, 1}, {1, 0, 0}};
  const auto path = (std::filesystem::path(temp_path("points.ply"))).string();
  ASSERT_TRUE(write_ply(
      path, {.positions = flat(points), .normals = flat(normals), .comments = {"made by a test"}}));
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string bytes = buffer.str();
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment made by a test\nelement vertex 2\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\nend_header\n";
  ASSERT_EQ(bytes.size(), header.size() + 48);  // 2 vertices of 6 floats
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  float body[12];
  std::memcpy(body, bytes.data() + header.size(), sizeof body);  // the test runs little-endian
  EXPECT_EQ(body[0], 1.5f);
  EXPECT_EQ(body[1], -2.0f);
  EXPECT_EQ(body[7], 0.25f);
  EXPECT_EQ(body[9], 1.0f);
  std::filesystem::remove(path);
  const std::vector<std::array<float, 3>> one_normal = {{0, 0, 1}};
  EXPECT_FALSE(write_ply(path, {.positions = flat(points), .normals = flat(one_normal)}));
}

TEST(PlyWrite, AColouredMeshReadsBackAsWritten) {
  const std::vector<std::array<float, 3>> points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5f}, {0, 1, 0}};
  const std::vector<std::array<uint8_t, 3>> colours = {
      {255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {9, 9, 9}};
  const std::vector<std::array<uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  const std::string path = temp_path("coloured.ply");
  ASSERT_TRUE(write_ply(
      path, {.positions = flat(points), .colours = flat(colours), .triangles = flat(triangles)}));
  const auto mesh = read_ply_mesh(path);
  ASSERT_TRUE(mesh) << mesh.error();
  ASSERT_EQ(mesh->vertices.size(), 4u);
  EXPECT_EQ(mesh->vertices[2].z, 0.5);
  ASSERT_EQ(mesh->triangles.size(), 2u);
  EXPECT_EQ(mesh->triangles[1], (std::array<uint32_t, 3>{0, 2, 3}));
  const std::vector<std::array<uint32_t, 3>> out_of_range = {{0, 1, 4}};
  const auto refused =
      write_ply(path, {.positions = flat(points), .triangles = flat(out_of_range)});
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("vertex 4 of 4"), std::string::npos) << refused.error();
}

}  // namespace
}  // namespace scancrew::io
