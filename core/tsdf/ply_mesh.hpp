#pragma once

// PLY export of a Mesh (binary_little_endian 1.0, Turk 1994): per vertex x y z nx ny nz
// (float) and, when coloured by owner, red green blue (uchar); per face a uchar count and
// int vertex indices. Readable by MeshLab, CloudCompare, Open3D and Blender.

#include <array>
#include <cstdint>
#include <string>

#include "core/result.hpp"
#include "core/tsdf/mesher.hpp"

namespace scancrew::tsdf {

enum class PlyColour : uint8_t {
  kNone,     // geometry and normals only
  kByOwner,  // each vertex in its block owner's colour (owner_colour)
};

// A fixed colour per robot id, distinct for ids 1..12 and repeating after: grey for 0
// (unknown / own).
std::array<uint8_t, 3> owner_colour(uint32_t owner);

// Writes the mesh to path (replacing it). On failure, a message naming the path and the
// system's reason; the file may be left partly written. Allocates one row buffer.
Result<void, std::string> write_ply(const Mesh& mesh, const std::string& path,
                                    PlyColour colour = PlyColour::kNone);

}  // namespace scancrew::tsdf
