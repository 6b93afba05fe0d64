#pragma once

// PLY point clouds for evaluation tools (CloudCompare, Open3D, PCL read them): binary
// little-endian, one vertex element of float x y z and, when normals are given, nx ny nz.

#include <array>
#include <string>
#include <vector>

#include "executors/result.hpp"

namespace scancrew::sim {

// normals: empty (points only) or one per point. Each comment becomes a `comment` line of
// the header (no line breaks). Errors name the file and the cause.
Result<void, std::string> write_ply(const std::string& path,
                                    const std::vector<std::array<float, 3>>& points,
                                    const std::vector<std::array<float, 3>>& normals,
                                    const std::vector<std::string>& comments = {});

}  // namespace scancrew::sim
