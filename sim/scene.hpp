#pragma once

// SceneSpec: a scene to reconstruct, as described in launch_cfg/scenes/*.yaml — floor,
// optional ceiling and walls around the bounds, boxes, cylinders, triangle meshes — random-dot
// textured so that stereo matching finds disparity, unless a file asks for plain (textureless)
// walls or objects. Turned into MJCF by build_mjcf(). Units: metres, radians; z up; the floor
// is z = 0.

#include <cstdint>
#include <string>
#include <vector>

#include "core/enum_names.hpp"
#include "core/result.hpp"
#include "interfaces/geometry.hpp"

namespace scancrew::sim {

struct Rgb {
  double r = 0.6, g = 0.6, b = 0.6;
};

// A surface's look: the random-dot texture (the default) or one flat colour, on which stereo
// matching finds no disparity (a painted wall; docs/simulator.md, "Plain surfaces").
enum class SurfaceTexture : uint8_t { kDots, kPlain };
inline constexpr EnumNames<SurfaceTexture, 2> kSurfaceTextureNames{{
    {SurfaceTexture::kDots, "dots"},
    {SurfaceTexture::kPlain, "plain"},
}};

struct BoxSpec {
  std::string name;
  msg::Vec3 center_m;
  msg::Vec3 size_m;  // full extents
  double yaw_rad = 0;
  Rgb color;
  SurfaceTexture texture = SurfaceTexture::kDots;
};

struct CylinderSpec {
  std::string name;
  msg::Vec3 center_m;
  double radius_m = 0, height_m = 0;
  Rgb color;
  SurfaceTexture texture = SurfaceTexture::kDots;
};

// A triangle mesh (any format assimp reads: COLLADA, OBJ, STL, PLY, ...; z up). It is scaled
// uniformly so its bounding box fits fit_m, then its bounding box is centred on center_m
// (x, y) and rests on z = center_m.z (sim/mesh_io.hpp). It is textured by box projection.
// Meshes are visual only: MuJoCo would collide with their convex hull, which would close
// every passage of a building, so robot contacts with meshes are not counted.
struct MeshSpec {
  std::string name;
  std::string file;  // absolute path, resolved by the loader
  msg::Vec3 fit_m;   // the box the mesh is scaled to fit (keeps proportions)
  msg::Vec3 center_m;
  Rgb color;
  std::string attribution;  // shown wherever the scene is shipped
};

// A place a robot may start: x, y, z (a ground robot's z is 0: it stands on the floor), yaw.
struct StartPose {
  msg::Vec3 position_m;
  double yaw_rad = 0;
};

// Start poses the scene offers, per robot kind (the scene file's `starts:`); a launch file
// still says where each robot starts. Each is inside the bounds.
struct SceneStarts {
  std::vector<StartPose> ground, multirotor;
};

struct SceneSpec {
  std::string name;
  std::string source;      // the YAML file it came from
  msg::Vec3 min_m, max_m;  // bounds of the region to reconstruct (and of the walls)
  bool ceiling = false;
  double wall_height_m = 0;  // 0: no walls
  double wall_thickness_m = 0.1;
  SurfaceTexture walls_texture = SurfaceTexture::kDots;  // the walls and the ceiling
  std::vector<BoxSpec> boxes;
  std::vector<CylinderSpec> cylinders;
  std::vector<MeshSpec> meshes;
  double dot_size_m = 0.02;  // texel size of the random-dot texture
  uint64_t texture_seed = 1;
  SceneStarts starts;  // optional; empty lists when the file has none
};

// Reads and validates a scene file: missing mesh files, degenerate geometry (zero or
// negative sizes), objects outside the bounds, starts outside the bounds or not of the form
// [x, y, z, yaw_deg], and unknown keys are errors naming the file, the key and what is
// allowed.
Result<SceneSpec, std::vector<std::string>> load_scene(const std::string& path);
Result<SceneSpec, std::vector<std::string>> parse_scene(const std::string& yaml_text,
                                                        const std::string& label,
                                                        const std::string& base_dir);

}  // namespace scancrew::sim
