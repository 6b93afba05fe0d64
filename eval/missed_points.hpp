#pragma once

// Where the coverage is lost (`scancrew eval --missed`): the ground-truth points a mesh does
// not cover, counted by how far the mesh is from them and by which way their surface faces.
//
//   near   the mesh passes within 2 e_max: a surface reconstructed there but placed off by
//          one to two voxel half-diagonals (thin parts, pipes, rails and edges a voxel of r_v
//          cannot place), or a neighbouring surface;
//   off    within 4 e_max;
//   hole   no mesh within 4 e_max: nothing was seen there (a matter of exploration).
//   up / down: the point's normal within 45° of +z / −z; side: the rest.
//
// On the powerplant trio (docs/missions.md) this split says whether a coverage target needs
// more exploration (holes) or a finer map (near misses).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "core/io/triangle_mesh.hpp"
#include "core/result.hpp"

namespace scancrew::eval {

enum class MissBand : uint8_t { kNear, kOff, kHole };
enum class Facing : uint8_t { kUp, kSide, kDown };
inline constexpr size_t kMissBands = 3;
inline constexpr size_t kFacings = 3;

struct MissProfile {
  double e_max_m = 0;
  size_t points = 0;                                              // points profiled
  std::array<std::array<size_t, kMissBands>, kFacings> counts{};  // [facing][band]

  size_t count(Facing f, MissBand b) const {
    return counts[static_cast<size_t>(f)][static_cast<size_t>(b)];
  }
  size_t band_total(MissBand b) const;
  size_t facing_total(Facing f) const;
};

Facing facing_of(const std::array<float, 3>& normal);
const char* to_string(MissBand b);
const char* to_string(Facing f);

// points: the uncovered ground-truth points (a point within e_max counts as near); normals:
// one per point, any length but zero. Fails, naming the culprit, on: e_max not positive and
// finite, points and normals of different counts, a point or normal not finite or a zero
// normal, a mesh vertex not finite or a triangle index out of range. An empty mesh makes
// every point a hole.
Result<MissProfile, std::string> profile_misses(const io::TriangleMesh& mesh,
                                                std::span<const std::array<float, 3>> points,
                                                std::span<const std::array<float, 3>> normals,
                                                double e_max_m);

}  // namespace scancrew::eval
