// The mesher (marching cubes) on a plane integrated from depth frames and on a box written
// from its analytic signed distance (sdf_scenes.hpp): vertices within e_max = r_v·√3/2 of
// the true surface, the visible area covered, normals and windings facing outside, a closed
// box giving a closed mesh, incremental updates equal to a full remesh; the marching-cubes
// tables.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/tsdf/integrator.hpp"
#include "core/tsdf/marching_cubes_tables.hpp"
#include "core/tsdf/mesher.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "tests/core/tsdf/sdf_scenes.hpp"
#include "tests/core/tsdf/synthetic_depth.hpp"

namespace scancrew::tsdf {
namespace {

using test::Box;
using test::box_map;
using test::config;
using test::fill;
using test::indices;
using test::kF;
using test::kH;
using test::kW;
using test::wall_frame;

double e_max(double voxel_m) {
  return voxel_m * std::sqrt(3.0) / 2;
}

// --- mesh measures -----------------------------------------------------------------------

double area(const Mesh& m) {
  double a = 0;
  for (const Triangle& t : m.triangles)
    a += 0.5 * (m.vertices[t[1]] - m.vertices[t[0]])
                   .cross(m.vertices[t[2]] - m.vertices[t[0]])
                   .cast<double>()
                   .norm();
  return a;
}

Eigen::Vector3f face_normal(const Mesh& m, const Triangle& t) {
  return (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
}

// The triangles as sets of corner positions, independent of vertex numbering and order.
std::multiset<std::vector<float>> triangle_set(const Mesh& m) {
  std::multiset<std::vector<float>> out;
  for (const Triangle& t : m.triangles) {
    std::vector<std::vector<float>> corners;
    for (uint32_t i : t)
      corners.push_back({m.vertices[i].x(), m.vertices[i].y(), m.vertices[i].z()});
    // rotate so the smallest corner comes first, keeping the winding
    const auto first = std::min_element(corners.begin(), corners.end());
    std::rotate(corners.begin(), first, corners.end());
    std::vector<float> flat;
    for (const auto& c : corners) flat.insert(flat.end(), c.begin(), c.end());
    out.insert(flat);
  }
  return out;
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (size_t i = 0; i < a.vertices.size(); ++i) {
    ASSERT_EQ(a.vertices[i], b.vertices[i]) << i;
    ASSERT_EQ(a.normals[i], b.normals[i]) << i;
    ASSERT_EQ(a.owners[i], b.owners[i]) << i;
  }
  for (size_t i = 0; i < a.triangles.size(); ++i) ASSERT_EQ(a.triangles[i], b.triangles[i]) << i;
  EXPECT_EQ(triangle_set(a), triangle_set(b));
}

// --- tables ------------------------------------------------------------------------------

TEST(MarchingCubesTables, EdgeMasksAreTheEdgesTheTrianglesUseAndTheSignChanges) {
  const McTables& t = mc_tables();
  for (int config = 0; config < 256; ++config) {
    const auto c = static_cast<size_t>(config);
    uint16_t used = 0;
    size_t k = 0;
    for (; k < 16 && t.triangles[c][k] >= 0; ++k)
      used |= static_cast<uint16_t>(1u << t.triangles[c][k]);
    EXPECT_EQ(k % 3, 0u) << config;
    EXPECT_LE(k, 15u) << config;
    EXPECT_EQ(used, t.edges[c]) << config;
    // an edge is cut exactly when its corners are on different sides
    uint16_t sign_change = 0;
    for (size_t j = 0; j < 12; ++j) {
      const bool a = (config >> kMcEdgeCorners[j][0]) & 1, b = (config >> kMcEdgeCorners[j][1]) & 1;
      if (a != b) sign_change |= static_cast<uint16_t>(1u << j);
    }
    EXPECT_EQ(sign_change, t.edges[c]) << config;
    EXPECT_EQ(t.edges[c], t.edges[255 - c]) << config;
  }
}

// --- geometry ----------------------------------------------------------------------------

TEST(Mesher, APlaneFromDepthFramesLiesWithinEmaxAndCoversTheVisibleArea) {
  TsdfConfig c = config(0.1);
  c.weight = TsdfWeight::kConstant;  // with 1/z² the frustum's far corners stay below w_th
  TsdfMap map(c);
  Integrator integrator(c);
  const double wall_x = 3.03;
  const std::vector<float> depth(static_cast<size_t>(kW) * kH, static_cast<float>(wall_x));
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(integrator.integrate(map, wall_frame(depth)));
  Mesher mesher;
  const MeshStats stats = mesher.full(*map.snapshot());
  EXPECT_TRUE(stats.full);
  EXPECT_EQ(stats.meshed_blocks, map.block_count());
  const Mesh mesh = mesher.assemble();
  ASSERT_GT(mesh.triangles.size(), 1000u);
  EXPECT_EQ(stats.triangles, mesh.triangles.size());

  double max_error = 0;
  for (const Eigen::Vector3f& v : mesh.vertices)
    max_error = std::max(max_error, std::abs(v.x() - wall_x));
  EXPECT_LE(max_error, e_max(c.voxel_m));
  EXPECT_LT(max_error, 0.01);  // a plane is linear in the TSDF: interpolation is exact

  // the wall seen through the frustum: 2·x·(W/2)/f by 2·x·(H/2)/f; the mesh loses at most
  // the cubes along the border of the observed area
  const double visible = (2 * wall_x * (kW / 2.0) / kF) * (2 * wall_x * (kH / 2.0) / kF);
  const double perimeter = 2 * (2 * wall_x * (kW / 2.0) / kF + 2 * wall_x * (kH / 2.0) / kF);
  const double a = area(mesh);
  EXPECT_LE(a, visible);
  EXPECT_GE(a, visible - perimeter * 2 * c.voxel_m) << "visible " << visible;
  std::cout << "plane: mesh area " << a << " m² of " << visible << " m² visible\n";

  // normals and windings face the camera (outside: −x)
  for (const Eigen::Vector3f& n : mesh.normals) ASSERT_GT(n.dot(-Eigen::Vector3f::UnitX()), 0.99f);
  for (const Triangle& t : mesh.triangles)
    ASSERT_GT(face_normal(mesh, t).normalized().dot(-Eigen::Vector3f::UnitX()), 0.99f);
}

TEST(Mesher, ABoxLiesWithinEmaxWithNormalsOutsideAndMakesAClosedMesh) {
  const Box box;
  TsdfMap map = box_map(box);
  const double r = map.config().voxel_m;
  Mesher mesher;
  mesher.full(*map.snapshot());
  const Mesh mesh = mesher.assemble(Weld::kAcrossBlocks);
  ASSERT_GT(mesh.triangles.size(), 1000u);

  size_t rough_normals = 0;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d p = mesh.vertices[i].cast<double>();
    ASSERT_LE(std::abs(box.sdf(p)), e_max(r)) << p.transpose();
    const double agree = mesh.normals[i].cast<double>().dot(box.gradient(p));
    ASSERT_GT(agree, 0.0) << p.transpose();  // never inward
    if (agree < 0.9) ++rough_normals;        // only at the box's edges and corners
    ASSERT_NEAR(mesh.normals[i].norm(), 1.0f, 1e-5f);
  }
  EXPECT_LT(rough_normals, mesh.vertices.size() / 10);
  for (const Triangle& t : mesh.triangles) {
    const Eigen::Vector3f centroid =
        (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3;
    ASSERT_GT(face_normal(mesh, t).dot(centroid - box.centre.cast<float>()), 0.0f);
  }
  // area: the linear interpolation cuts the box's edges (less than a chamfer with legs of
  // one voxel: (2 − √2)·r_v per metre of edge) and corners
  const double a = area(mesh);
  EXPECT_LE(a, box.area());
  EXPECT_GE(a, box.area() - box.edge_length() * (2 - std::sqrt(2.0)) * r);

  // closed and consistently wound: every edge in exactly two triangles, once each way;
  // a sphere's Euler characteristic
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    ASSERT_EQ(count, 1) << edge.first << "-" << edge.second;
    ASSERT_EQ(directed.count({edge.second, edge.first}), 1u) << edge.first << "-" << edge.second;
  }
  const auto v = static_cast<long>(mesh.vertices.size()),
             e = static_cast<long>(directed.size() / 2),
             f = static_cast<long>(mesh.triangles.size());
  EXPECT_EQ(v - e + f, 2);

  // without welding across blocks: the same triangles, more vertices
  const Mesh unwelded = mesher.assemble();
  EXPECT_EQ(unwelded.triangles.size(), mesh.triangles.size());
  EXPECT_GT(unwelded.vertices.size(), mesh.vertices.size());
  EXPECT_EQ(triangle_set(unwelded), triangle_set(mesh));
}

TEST(Mesher, CubesWithAnUnobservedCornerMakeNoSurface) {
  const Box box;
  const double r = box_map(box).config().voxel_m;
  // the box's +x half set to weight w: observed only from the −x side
  const double cut_x = box.centre.x() + 0.01;
  auto cut_map = [&](float w) {
    TsdfMap map = box_map(box);
    const uint64_t sequence = map.begin_update();
    for (const BlockIndex& index : indices(map)) {
      Block* block = map.find_mutable(index);
      for (int z = 0; z < kBlockSide; ++z)
        for (int y = 0; y < kBlockSide; ++y)
          for (int x = 0; x < kBlockSide; ++x)
            if (voxel_center(index * kBlockSide + Eigen::Vector3i(x, y, z), r).x() > cut_x)
              block->at(x, y, z).weight = w;
      block->modified = sequence;
    }
    return map;
  };
  auto expect_half = [&](const Mesh& half) {
    ASSERT_GT(half.triangles.size(), 100u);
    for (const Eigen::Vector3f& v : half.vertices) ASSERT_LT(v.x(), cut_x);  // nothing past the cut
    // no closing cap at the unknown border: about half the box's area
    EXPECT_NEAR(area(half), box.area() / 2, 0.06 * box.area());
  };
  Mesher all_known;
  all_known.full(*box_map(box).snapshot());

  // weight 0: never observed, so not meshed by default
  Mesher observed;
  observed.full(*cut_map(0.0f).snapshot());
  expect_half(observed.assemble());

  // weight 0.2: observed (meshed by default) but not known (below W_th = 0.3)
  const TsdfMap faint = cut_map(0.2f);
  Mesher by_default;
  by_default.full(*faint.snapshot());
  expect_same_mesh(by_default.assemble(), all_known.assemble());
  Mesher known_only(MesherConfig{.min_weight = faint.config().w_th});
  known_only.full(*faint.snapshot());
  expect_half(known_only.assemble());
}

// --- incremental -------------------------------------------------------------------------

TEST(Mesher, AnIncrementalUpdateEqualsAFullRemesh) {
  const Box box;
  TsdfMap map = box_map(box);
  Mesher incremental;
  const MeshStats first = incremental.update(*map.snapshot());
  EXPECT_TRUE(first.full);  // the first update meshes everything
  const Mesh before = incremental.assemble();

  // a bump on the top face (a small sphere joined to the box) and a hole where one block
  // is removed, as one map update; a separate new blob
  const Eigen::Vector3d bump = box.centre + Eigen::Vector3d(0.1, 0.05, box.half.z());
  const auto with_bump = [&](const Eigen::Vector3d& p) {
    return std::min(box.sdf(p), (p - bump).norm() - 0.12);
  };
  fill(map, with_bump, bump - Eigen::Vector3d::Constant(0.2), bump + Eigen::Vector3d::Constant(0.2),
       1, 2);
  const BlockIndex removed =
      block_of(voxel_of(box.centre - Eigen::Vector3d(box.half.x(), 0, 0), 0.05));
  ASSERT_NE(map.find(removed), nullptr);
  map.erase(removed);
  const Eigen::Vector3d blob(2.0, 2.0, 0.0);
  fill(
      map, [&](const Eigen::Vector3d& p) { return (p - blob).norm() - 0.2; },
      blob - Eigen::Vector3d::Constant(0.4), blob + Eigen::Vector3d::Constant(0.4), 1, 3);

  const auto snap = map.snapshot();
  const MeshStats stats = incremental.update(*snap);
  EXPECT_FALSE(stats.full);
  EXPECT_EQ(stats.removed_blocks, 1u);
  EXPECT_GT(stats.changed_blocks, 0u);
  EXPECT_LT(stats.meshed_blocks, snap->block_count() / 2);
  EXPECT_EQ(incremental.blocks().size(), snap->block_count());
  EXPECT_EQ(incremental.sequence(), snap->sequence());

  Mesher full;
  full.full(*snap);
  const Mesh after = incremental.assemble();
  expect_same_mesh(after, full.assemble());
  expect_same_mesh(incremental.assemble(Weld::kAcrossBlocks), full.assemble(Weld::kAcrossBlocks));
  EXPECT_NE(triangle_set(after), triangle_set(before));  // the change is in the mesh
  // the bump's and the blob's vertices carry their blocks' owners
  std::set<uint32_t> owners(after.owners.begin(), after.owners.end());
  EXPECT_EQ(owners, (std::set<uint32_t>{0, 2, 3}));

  // nothing changed: nothing remeshed, the same mesh
  const MeshStats idle = incremental.update(*map.snapshot());
  EXPECT_EQ(idle.meshed_blocks, 0u);
  expect_same_mesh(incremental.assemble(), after);
}

TEST(Mesher, MeshesALargeMapAndReportsTheTime) {
  // the shell of a 10 m × 10 m × 3 m room at 5 cm voxels
  Box room;
  room.centre = {0.0, 0.0, 1.5};
  room.half = {5.0, 5.0, 1.5};
  TsdfMap map(config(0.05));
  const auto inside_out = [&](const Eigen::Vector3d& p) { return -room.sdf(p); };
  fill(map, inside_out, room.centre - room.half - Eigen::Vector3d::Constant(0.3),
       room.centre + room.half + Eigen::Vector3d::Constant(0.3), 1, 1,
       map.config().truncation_m + 0.1);
  Mesher mesher;
  MeshStats full = mesher.full(*map.snapshot());
  for (int i = 0; i < 2; ++i) {  // the best of three
    const MeshStats again = mesher.full(*map.snapshot());
    if (again.seconds < full.seconds) full = again;
  }
  const Mesh mesh = mesher.assemble();
  EXPECT_NEAR(area(mesh), room.area(), 0.01 * room.area());

  // one wall patch changed
  const Eigen::Vector3d spot(5.0, 1.0, 1.0);
  fill(
      map,
      [&](const Eigen::Vector3d& p) { return std::min(inside_out(p), (p - spot).norm() - 0.3); },
      spot - Eigen::Vector3d::Constant(0.5), spot + Eigen::Vector3d::Constant(0.5), 1, 2);
  const MeshStats local = mesher.update(*map.snapshot());
  EXPECT_LT(local.meshed_blocks, 200u);
  std::cout << "full: " << full.meshed_blocks << " blocks, " << full.triangles << " triangles in "
            << full.seconds * 1e3 << " ms; incremental: " << local.changed_blocks << " changed, "
            << local.meshed_blocks << " remeshed in " << local.seconds * 1e3 << " ms\n";
  ::testing::Test::RecordProperty("full_blocks", std::to_string(full.meshed_blocks));
  ::testing::Test::RecordProperty("full_ms", std::to_string(full.seconds * 1e3));
  ::testing::Test::RecordProperty("incremental_ms", std::to_string(local.seconds * 1e3));
}

}  // namespace
}  // namespace scancrew::tsdf
