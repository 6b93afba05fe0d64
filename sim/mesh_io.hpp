#pragma once

// Triangle meshes of a scene: read with assimp (COLLADA, OBJ, STL, PLY, ...), placed as the
// scene asks (uniform scale to fit a box, centred in x-y, resting on a height), and written
// as an OBJ that MuJoCo 2.2 reads, with texture coordinates so that the random-dot texture
// covers every face (the Power Plant model has no usable UVs).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/io/triangle_mesh.hpp"
#include "core/result.hpp"
#include "interfaces/geometry.hpp"
#include "sim/scene.hpp"

namespace scancrew::sim {

using io::TriangleMesh;

// Whether load_mesh reads files with this extension (".dae", ".obj", ...).
bool mesh_format_supported(const std::string& extension);

// Reads every triangle of every mesh of the file, with node transforms applied, in the
// file's own axes (COLLADA's up-axis conversion is disabled: scenes are z-up). Errors name
// the file and the cause; a file with no triangles is an error.
Result<TriangleMesh, std::string> load_mesh(const std::string& path);

// The mesh scaled uniformly so its bounding box fits spec.fit_m (keeping proportions), its
// bounding box centred on spec.center_m in x-y, its lowest point at spec.center_m.z.
TriangleMesh place_mesh(const TriangleMesh& mesh, const MeshSpec& spec);

// Loads and places every mesh of the scene (load_mesh + place_mesh), in scene order.
Result<std::vector<TriangleMesh>, std::string> load_scene_meshes(const SceneSpec& scene);

// Writes an OBJ with a texture coordinate per triangle corner: each triangle is projected on
// the axis plane most facing it (a box projection), one texture repeat per texture_period_m,
// so the texture shows at the same scale on every face whatever its orientation.
Result<void, std::string> write_textured_obj(const TriangleMesh& mesh, double texture_period_m,
                                             const std::string& path);

}  // namespace scancrew::sim
