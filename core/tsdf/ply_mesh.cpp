#include "core/tsdf/ply_mesh.hpp"

#include <vector>

#include "core/io/ply.hpp"

namespace scancrew::tsdf {

std::array<uint8_t, 3> owner_colour(uint32_t owner) {
  // Okabe & Ito's colour-blind safe set, then a few of Tableau 10
  static constexpr std::array<std::array<uint8_t, 3>, 12> kPalette = {{
      {230, 159, 0},
      {86, 180, 233},
      {0, 158, 115},
      {240, 228, 66},
      {0, 114, 178},
      {213, 94, 0},
      {204, 121, 167},
      {148, 103, 189},
      {140, 86, 75},
      {188, 189, 34},
      {23, 190, 207},
      {214, 39, 40},
  }};
  if (owner == 0) return {128, 128, 128};
  return kPalette[(owner - 1) % kPalette.size()];
}

Result<void, std::string> write_ply(const Mesh& mesh, const std::string& path, PlyColour colour) {
  std::vector<std::array<uint8_t, 3>> colours;
  if (colour == PlyColour::kByOwner) {
    if (mesh.owners.size() != mesh.vertices.size())
      return make_unexpected("cannot write " + path + ": the mesh has " +
                             std::to_string(mesh.vertices.size()) + " vertices but " +
                             std::to_string(mesh.owners.size()) + " owners");
    colours.reserve(mesh.owners.size());
    for (const uint32_t owner : mesh.owners) colours.push_back(owner_colour(owner));
  }
  return io::write_ply(path, {.positions = io::flat(mesh.vertices),
                              .normals = io::flat(mesh.normals),
                              .colours = io::flat(colours),
                              .triangles = io::flat(mesh.triangles),
                              .comments = {"scancrew TSDF mesh"},
                              .mesh = true});
}

}  // namespace scancrew::tsdf
