// The mesh and map exports: the PLY file read back by a small parser here; the OctoMap file
// read back by OctoMap (scenes from sdf_scenes.hpp).

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/ply.hpp"
#include "core/tsdf/integrator.hpp"
#include "core/tsdf/mesher.hpp"
#include "core/tsdf/octomap_export.hpp"
#include "core/tsdf/ply_mesh.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "tests/core/tsdf/sdf_scenes.hpp"
#include "tests/core/tsdf/synthetic_depth.hpp"

namespace scancrew::tsdf {
namespace {

using test::Box;
using test::box_map;
using test::config;
using test::indices;
using test::kH;
using test::kW;
using test::wall_frame;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("scancrew_test_mesh_" +
           std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" + name))
      .string();
}

// --- PLY ---------------------------------------------------------------------------------

struct PlyFile {
  std::vector<std::string> header;
  std::string body;
};

PlyFile read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream all;
  all << in.rdbuf();
  const std::string text = all.str();
  const std::string end = "end_header\n";
  const size_t at = text.find(end);
  PlyFile f;
  if (at == std::string::npos) return f;
  std::istringstream lines(text.substr(0, at));
  for (std::string line; std::getline(lines, line);) f.header.push_back(line);
  f.body = text.substr(at + end.size());
  return f;
}

template <class T>
T read_at(const std::string& body, size_t offset) {
  T value;
  std::memcpy(&value, body.data() + offset, sizeof(T));
  return value;
}

TEST(PlyMesh, WritesBinaryVerticesNormalsOwnerColoursAndFacesThatReadBack) {
  const Box box;
  TsdfMap map = box_map(box);
  // the −x half of the box belongs to robot 1, the rest to robot 0
  for (const BlockIndex& index : indices(map))
    if (index.x() * kBlockSide * 0.05 < box.centre.x()) map.find_mutable(index)->owner = 1;
  Mesher mesher;
  mesher.full(*map.snapshot());
  const Mesh mesh = mesher.assemble(Weld::kAcrossBlocks);

  for (const PlyColour colour : {PlyColour::kByOwner, PlyColour::kNone}) {
    const bool rgb = colour == PlyColour::kByOwner;
    const std::string path = temp_path(rgb ? "owner.ply" : "plain.ply");
    ASSERT_TRUE(write_ply(mesh, path, colour));
    const PlyFile ply = read_ply(path);
    std::vector<std::string> expected = {"ply",
                                         "format binary_little_endian 1.0",
                                         "comment scancrew TSDF mesh",
                                         "element vertex " + std::to_string(mesh.vertices.size()),
                                         "property float x",
                                         "property float y",
                                         "property float z",
                                         "property float nx",
                                         "property float ny",
                                         "property float nz"};
    if (rgb)
      for (const char* c : {"red", "green", "blue"})
        expected.push_back(std::string("property uchar ") + c);
    expected.push_back("element face " + std::to_string(mesh.triangles.size()));
    expected.push_back("property list uchar int vertex_indices");
    EXPECT_EQ(ply.header, expected);

    const size_t vertex_bytes = 24 + (rgb ? 3 : 0), face_bytes = 1 + 12;
    ASSERT_EQ(ply.body.size(),
              mesh.vertices.size() * vertex_bytes + mesh.triangles.size() * face_bytes);
    std::set<uint32_t> colours_seen;
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      const size_t at = i * vertex_bytes;
      for (Eigen::Index k = 0; k < 3; ++k) {
        ASSERT_EQ(read_at<float>(ply.body, at + 4 * static_cast<size_t>(k)), mesh.vertices[i][k]);
        ASSERT_EQ(read_at<float>(ply.body, at + 12 + 4 * static_cast<size_t>(k)),
                  mesh.normals[i][k]);
      }
      if (rgb) {
        const auto c = owner_colour(mesh.owners[i]);
        for (size_t k = 0; k < 3; ++k) ASSERT_EQ(read_at<uint8_t>(ply.body, at + 24 + k), c[k]);
        colours_seen.insert(read_at<uint8_t>(ply.body, at + 24));
      }
    }
    if (rgb) {
      EXPECT_EQ(colours_seen.size(), 2u);  // grey and robot 1's
    }
    const size_t faces_at = mesh.vertices.size() * vertex_bytes;
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
      const size_t at = faces_at + i * face_bytes;
      ASSERT_EQ(read_at<uint8_t>(ply.body, at), 3);
      for (size_t k = 0; k < 3; ++k)
        ASSERT_EQ(read_at<int32_t>(ply.body, at + 1 + 4 * k),
                  static_cast<int32_t>(mesh.triangles[i][k]));
    }
    std::filesystem::remove(path);
  }
  EXPECT_EQ(owner_colour(0), (std::array<uint8_t, 3>{128, 128, 128}));
  EXPECT_NE(owner_colour(1), owner_colour(2));
}

TEST(PlyMesh, AnEmptyMeshIsAValidFileAndBadPathsAreNamed) {
  const std::string path = temp_path("empty.ply");
  ASSERT_TRUE(write_ply(Mesh{}, path, PlyColour::kByOwner));
  const PlyFile ply = read_ply(path);
  EXPECT_NE(std::find(ply.header.begin(), ply.header.end(), "element vertex 0"), ply.header.end());
  EXPECT_NE(std::find(ply.header.begin(), ply.header.end(), "element face 0"), ply.header.end());
  EXPECT_TRUE(ply.body.empty());
  // still a mesh to the reader (the evaluation scores it as empty, not as a point cloud)
  const auto back = io::read_ply_mesh(path);
  ASSERT_TRUE(back) << back.error();
  EXPECT_TRUE(back->triangles.empty());
  std::filesystem::remove(path);

  const std::string bad = "/nonexistent_dir_scancrew/mesh.ply";
  const auto r = write_ply(Mesh{}, bad);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find(bad), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("No such file or directory"), std::string::npos) << r.error();

  Mesh broken;
  broken.vertices.resize(2);
  broken.normals.resize(2);
  broken.triangles.push_back({0, 1, 2});
  EXPECT_FALSE(write_ply(broken, path));
  EXPECT_FALSE(std::filesystem::exists(path));
  Mesh no_normals;  // a mesh's vertices need their normals
  no_normals.vertices.resize(3);
  no_normals.triangles.push_back({0, 1, 2});
  EXPECT_FALSE(write_ply(no_normals, path));
  EXPECT_FALSE(std::filesystem::exists(path));
}

// --- OctoMap -----------------------------------------------------------------------------

TEST(OctomapExport, KnownVoxelsReadBackAsOccupiedOrFreeAndUnknownAsUnknown) {
  const TsdfConfig c = config(0.1);
  TsdfMap map(c);
  Integrator integrator(c);
  const std::vector<float> depth(static_cast<size_t>(kW) * kH, 3.03f);
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(integrator.integrate(map, wall_frame(depth)));
  const auto snap = map.snapshot();

  const std::string path = temp_path("map.bt");
  const auto stats = write_octomap(*snap, path);
  ASSERT_TRUE(stats) << stats.error();
  size_t occupied = 0, known = 0;
  const auto w_th = static_cast<float>(c.w_th);
  for (const auto& [index, block] : snap->blocks())
    for (const Voxel& v : block->voxels) {
      if (state_of(v, w_th) == VoxelState::kUnknown) continue;
      ++known;
      if (state_of(v, w_th) == VoxelState::kOccupied) ++occupied;
    }
  EXPECT_EQ(stats->occupied, occupied);
  EXPECT_EQ(stats->free, known - occupied);
  EXPECT_EQ(stats->out_of_range, 0u);
  EXPECT_EQ(stats->bytes, std::filesystem::file_size(path));
  EXPECT_GT(stats->occupied, 1000u);

  octomap::OcTree tree(path);
  EXPECT_DOUBLE_EQ(tree.getResolution(), c.voxel_m);
  // leaves, pruned ones counted by the voxels they stand for
  size_t tree_occupied = 0, tree_free = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    const size_t voxels = size_t{1} << (3 * (tree.getTreeDepth() - it.getDepth()));
    (tree.isNodeOccupied(*it) ? tree_occupied : tree_free) += voxels;
  }
  EXPECT_EQ(tree_occupied, occupied);
  EXPECT_EQ(tree_free, known - occupied);

  // sample points: along the optical axis, and every voxel of one block at the wall
  const auto expect_state = [&](const Eigen::Vector3d& p) {
    const VoxelState s = snap->state_at(p);
    const octomap::OcTreeNode* node = tree.search(p.x(), p.y(), p.z());
    if (s == VoxelState::kUnknown) {
      EXPECT_EQ(node, nullptr) << p.transpose();
      return;
    }
    ASSERT_NE(node, nullptr) << p.transpose();
    EXPECT_EQ(tree.isNodeOccupied(node), s == VoxelState::kOccupied) << p.transpose();
  };
  for (double x = -1.0; x < 4.0; x += 0.05) expect_state({x, 0.01, 0.01});
  expect_state({1.0, 0.01, 0.01});
  EXPECT_EQ(snap->state_at({3.08, 0.01, 0.01}), VoxelState::kOccupied);
  EXPECT_TRUE(tree.isNodeOccupied(tree.search(3.08, 0.01, 0.01)));
  EXPECT_FALSE(tree.isNodeOccupied(tree.search(2.0, 0.5, -0.3)));
  const BlockIndex wall = block_of(voxel_of({3.03, 0.4, -0.4}, c.voxel_m));
  for (int z = 0; z < kBlockSide; ++z)
    for (int y = 0; y < kBlockSide; ++y)
      for (int x = 0; x < kBlockSide; ++x)
        expect_state(voxel_center(wall * kBlockSide + Eigen::Vector3i(x, y, z), c.voxel_m));
  std::filesystem::remove(path);
}

TEST(OctomapExport, VoxelsBeyondTheKeyRangeAreSkippedAndCounted) {
  TsdfMap map(config(0.1));
  const uint64_t sequence = map.begin_update();
  for (const BlockIndex& b : {BlockIndex(0, 0, 0), BlockIndex(5000, 0, 0)}) {  // 4 km away
    Block& block = map.touch(b);
    for (Voxel& v : block.voxels) v = {-0.05f, 1.0f};
    block.modified = sequence;
  }
  const std::string path = temp_path("far.bt");
  const auto stats = write_octomap(*map.snapshot(), path);
  ASSERT_TRUE(stats) << stats.error();
  EXPECT_EQ(stats->occupied, static_cast<size_t>(kBlockVoxels));
  EXPECT_EQ(stats->out_of_range, static_cast<size_t>(kBlockVoxels));
  EXPECT_EQ(stats->leaf_nodes, 1u);  // the 8³ occupied voxels pruned into one node
  std::filesystem::remove(path);

  const auto bad = write_octomap(*map.snapshot(), "/nonexistent_dir_scancrew/map.bt");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("/nonexistent_dir_scancrew/map.bt"), std::string::npos);
  EXPECT_NE(bad.error().find("No such file or directory"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace scancrew::tsdf
