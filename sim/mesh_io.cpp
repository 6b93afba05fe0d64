#include "sim/mesh_io.hpp"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "core/vec3_math.hpp"

namespace scancrew::sim {

using vec3::cross;
using vec3::sub;

bool mesh_format_supported(const std::string& extension) {
  return !extension.empty() && Assimp::Importer().IsExtensionSupported(extension);
}

Result<TriangleMesh, std::string> load_mesh(const std::string& path) {
  if (!std::filesystem::exists(path))
    return make_unexpected("mesh file '" + path + "' does not exist");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return make_unexpected("mesh file '" + path +
                           "' is not a regular file (a device, a pipe or a folder)");
  Assimp::Importer importer;
  // scenes are z-up like the COLLADA models we ship; keep the file's axes
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // lines and points (SketchUp exports edges) are dropped, not turned into degenerate triangles
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_LINE | aiPrimitiveType_POINT);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                  aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                                  aiProcess_FindDegenerates);
  if (scene == nullptr)
    return make_unexpected("mesh file '" + path + "': " + importer.GetErrorString());
  TriangleMesh mesh;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    const auto base = static_cast<uint32_t>(mesh.vertices.size());
    for (unsigned v = 0; v < in->mNumVertices; ++v) {
      const aiVector3D& p = in->mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        return make_unexpected("mesh file '" + path + "': vertex " + std::to_string(v) +
                               " of mesh " + std::to_string(m) + " is not finite");
      mesh.vertices.push_back({p.x, p.y, p.z});
    }
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices != 3) continue;
      // the importer's indices are the file's: checked before they index the vertices
      for (unsigned i = 0; i < 3; ++i)
        if (face.mIndices[i] >= in->mNumVertices)
          return make_unexpected("mesh file '" + path + "': face " + std::to_string(f) +
                                 " of mesh " + std::to_string(m) + " refers to vertex " +
                                 std::to_string(face.mIndices[i]) + " of " +
                                 std::to_string(in->mNumVertices));
      mesh.triangles.push_back(
          {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  if (mesh.triangles.empty()) return make_unexpected("mesh file '" + path + "' holds no triangles");
  const msg::Vec3 lo = mesh.min(), hi = mesh.max();
  if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z))
    return make_unexpected("mesh file '" + path + "' is flat or degenerate (empty bounding box)");
  return mesh;
}

TriangleMesh place_mesh(const TriangleMesh& mesh, const MeshSpec& spec) {
  const msg::Vec3 lo = mesh.min(), hi = mesh.max();
  const double scale = std::min(
      {spec.fit_m.x / (hi.x - lo.x), spec.fit_m.y / (hi.y - lo.y), spec.fit_m.z / (hi.z - lo.z)});
  const double cx = 0.5 * (lo.x + hi.x), cy = 0.5 * (lo.y + hi.y);
  TriangleMesh out;
  out.triangles = mesh.triangles;
  out.vertices.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices)
    out.vertices.push_back({spec.center_m.x + scale * (v.x - cx),
                            spec.center_m.y + scale * (v.y - cy),
                            spec.center_m.z + scale * (v.z - lo.z)});
  return out;
}

Result<std::vector<TriangleMesh>, std::string> load_scene_meshes(const SceneSpec& scene) {
  std::vector<TriangleMesh> meshes;
  for (const MeshSpec& spec : scene.meshes) {
    auto mesh = load_mesh(spec.file);
    if (!mesh) return make_unexpected("mesh '" + spec.name + "': " + mesh.error());
    meshes.push_back(place_mesh(*mesh, spec));
  }
  return meshes;
}

Result<void, std::string> write_textured_obj(const TriangleMesh& mesh, double texture_period_m,
                                             const std::string& path) {
  std::ofstream out(path);
  if (!out) return make_unexpected("cannot write '" + path + "'");
  out.precision(9);
  out << "# written by scancrew (sim/mesh_io.cpp): box-projected texture coordinates\n";
  // one vertex and one texture coordinate per triangle corner (flat shading, and MuJoCo
  // 2.2 wants vertex and texture coordinate indices to agree); each triangle is projected
  // on the axis plane most facing it
  for (const auto& t : mesh.triangles) {
    const msg::Vec3& a = mesh.vertices[t[0]];
    const msg::Vec3 n = cross(sub(mesh.vertices[t[1]], a), sub(mesh.vertices[t[2]], a));
    const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
    for (const uint32_t i : t) {
      const msg::Vec3& v = mesh.vertices[i];
      double u = v.y, w = v.z;  // facing x
      if (az >= ax && az >= ay) {
        u = v.x, w = v.y;
      } else if (ay >= ax) {
        u = v.x, w = v.z;
      }
      out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n'
          << "vt " << u / texture_period_m << ' ' << w / texture_period_m << '\n';
    }
  }
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    out << "f";
    for (size_t c = 1; c <= 3; ++c) out << ' ' << 3 * k + c << '/' << 3 * k + c;
    out << '\n';
  }
  out.close();
  if (!out) return make_unexpected("cannot write '" + path + "' (disk full?)");
  return {};
}

}  // namespace scancrew::sim
