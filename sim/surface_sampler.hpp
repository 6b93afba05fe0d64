#pragma once

// Ground truth for evaluating a reconstruction: dense points with outward unit normals on
// the scene's visible surfaces, at a given density (the thesis uses 10 000 points/m²).
//
// Sampled: the floor over the bounds (+z), the ceiling's underside over the bounds (-z,
// when the scene has one), the inner faces of the four walls from z = 0 to the wall height,
// the six faces of every box (turned by its yaw), the side and both disks of every cylinder
// (sampled analytically, not tessellated), and every triangle of the placed meshes (normal
// from the winding, right-handed). Each surface gets floor(area · density + u) points, u
// uniform in [0, 1), uniform over the surface, from one std::mt19937_64 seeded with `seed`:
// the same scene, meshes and options give the same points, bit for bit (on one build: the
// RNG is portable, libm's sin and cos need not be).
//
// Hidden points are dropped: a point is hidden when it lies inside a solid other than the
// one it was sampled from, each solid expanded by kHiddenTolerance — the boxes, cylinders,
// wall slabs, ceiling slab (as build_mjcf() places them) and the floor as the half-space
// z < 0 — or outside the bounds expanded by the same tolerance. That removes faces resting
// on the floor or on the ceiling, the floor under obstacles, faces shared by two touching
// solids and whatever is buried in another solid; a band of kHiddenTolerance along every
// contact line goes too (about 1e-4 m² per metre of contact: negligible).
//
// Meshes are triangle soups, not solids, so the test above cannot see what a mesh closes in
// (a building's interior floors and partitions, the floor under it). With
// visibility_rays > 0 (the default) and meshes in the scene, every point is also tested by
// ray casting (MeshOcclusion, sim/mesh_occlusion.hpp): one that no ray leaves the meshes
// from is dropped, as the thesis prunes "all the invisible surfaces of the GT mesh" (2.6.2).
// Scenes without meshes are not affected. With visibility_rays = 0 a mesh's points are kept
// unless inside one of the solids above.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "sim/mesh_io.hpp"
#include "sim/scene.hpp"

namespace scancrew::sim {

inline constexpr double kHiddenTolerance = 1e-4;  // m

struct SamplingOptions {
  double density_per_m2 = 10000;
  uint64_t seed = 1;
  // refused beyond this (before sampling) instead of filling memory: 24 bytes a point
  size_t max_points = 50'000'000;
  // directions tried per point by the mesh visibility test (besides the normal and its
  // reverse); 0 turns the test off. Negative is refused.
  int visibility_rays = 64;
};

struct SurfaceSamples {
  std::vector<std::array<float, 3>> points;   // m, world frame
  std::vector<std::array<float, 3>> normals;  // unit, outward (towards the free space)
  // The visible area: over every surface that received samples, its area times the
  // fraction of its samples kept (a mesh counts as one surface, so that triangles too small
  // to receive a point do not bias it). Close to points.size() / density.
  double area_m2 = 0;
};

// `placed_meshes` are the scene's meshes as load_scene_meshes() returns them (any triangle
// meshes may be given; they need not match scene.meshes). Errors: a density that is not
// positive and finite, a negative visibility_rays, and a point count (density × total area before
// hiding) over max_points — the message gives both numbers and the highest density allowed.
Result<SurfaceSamples, std::string> sample_surfaces(const SceneSpec& scene,
                                                    const std::vector<TriangleMesh>& placed_meshes,
                                                    const SamplingOptions& options);

}  // namespace scancrew::sim
