#pragma once

// A picture of an IseResult for MeshLab / CloudCompare / Open3D: a PLY point cloud
// (core/io/ply.hpp) with per-point colour and view direction (as normals):
//   inspectable ISEs   green, normal = view direction
//   ISEs in C_rem      red
//   viewpoints         blue, normal = the camera's look direction; cluster centroids are
//                      not drawn (a cluster is its viewpoints)
// Load it over the mesh (tsdf_mapper's mesh_path) to see where the surface is incomplete.

#include <string>

#include "core/ise/ise_pipeline.hpp"
#include "core/result.hpp"

namespace scancrew::ise {

Result<void, std::string> write_ise_ply(const IseResult& result, const std::string& path);

}  // namespace scancrew::ise
