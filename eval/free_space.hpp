#pragma once

// FreeSpace: where a robot's body fits in a scene, and which of those places it can reach
// from its start — the first half of the reachable ground truth (eval/reachable_truth.hpp):
// a ground robot cannot see the top of a 5 m wall, nor a room behind a closed door.
//
// Ground robot: a 2D grid over the scene's bounds (SceneSpec::min_m / max_m, x-y), a cell
// free when the body's upright cylinder (radius_m, from clearance_m to height_m above the
// floor) at the cell's centre overlaps no solid and no mesh triangle; 4-connected flood fill
// from the starts. Multirotor: a 3D grid over the bounds (x-y) and the altitude band of the
// body centre (z), a cell free when the body's ball at its centre overlaps nothing;
// 6-connected. Cells outside the bounds are not part of the grid (an outdoor robot is taken
// to stay over the region it reconstructs). Solids and meshes: sim::SceneSolids.
//
// Seeds: a start's body is tested where it stands (start_free()); the flood starts from its
// cell, or when that cell's centre is not free, from the free cells of the 3 x 3 (x 3)
// block around it. A multirotor start outside the altitude band (on the ground before
// take-off) is moved into the band, straight up or down.
//
// Memory: one byte a cell. Immutable once built; const member functions are thread safe.

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "interfaces/geometry.hpp"
#include "sim/robot_model.hpp"
#include "sim/scene.hpp"
#include "sim/scene_solids.hpp"

namespace scancrew::eval {

// The body FreeSpace tests, from the kind's BodyModel (core/robot/body_model.hpp): its
// footprint radius, height and underside, and for a multirotor the band it flies in.
struct FreeSpaceBody {
  robot::RobotKind kind = robot::RobotKind::kGround;
  double radius_m = 0.3;  // ground: footprint disc radius; multirotor: body sphere radius
  double height_m = 0.4;  // ground: body height above the floor
  double min_altitude_m = 1.0, max_altitude_m = 20.0;  // multirotor: band of the body centre
  double clearance_m = 0.05;  // ground: the underside above the floor (lower steps are crossed)
};

// A kind's body (robot::BodyModel::of): ground, radius 0.25 m, the safety ellipse's minor
// semi-axis (the half width it needs to drive along a passage, facing it; it is not asked to
// turn on the spot there), height 0.4 m (body and camera), underside 0.05 m; multirotor,
// radius 1 m (the collision sphere of table 2.1), band 1 to 20 m.
FreeSpaceBody default_body(robot::RobotKind kind);

struct FreeSpaceOptions {
  double cell_m = 0.0;  // 0: 0.2 m ground, 0.5 m multirotor
};

class FreeSpace {
 public:
  // Errors: a body or cell size that is not positive and finite, an empty altitude band,
  // empty bounds, a grid over 2^31 cells, no starts.
  static Result<FreeSpace, std::string> build(const sim::SceneSolids& solids,
                                              const sim::SceneSpec& scene,
                                              const FreeSpaceBody& body,
                                              const std::vector<msg::Vec3>& starts,
                                              const FreeSpaceOptions& options = {});

  bool start_free(size_t i) const;  // start i's body fits where it stands
  bool connected() const;           // every free cell is reachable from some start
  size_t free_cells() const { return free_cells_; }
  size_t reachable_cells() const { return reachable_cells_; }
  bool reachable(const msg::Vec3& body_position) const;  // its cell is reachable
  // Body positions of reachable cells on a lattice of about spacing_m (ground: z = 0): one
  // per lattice block that holds a reachable cell, the one nearest the block's centre, so a
  // passage narrower than the spacing still gets positions.
  std::vector<msg::Vec3> reachable_positions(double spacing_m) const;

  const FreeSpaceBody& body() const { return body_; }
  double cell_m() const { return cell_m_; }
  // Body position of cell (i, j, k) (ground: k = 0, z = 0).
  msg::Vec3 cell_center(int64_t i, int64_t j, int64_t k) const;

 private:
  enum : uint8_t { kBlocked = 0, kFree = 1, kReachable = 2 };

  FreeSpace() = default;
  int64_t index(int64_t i, int64_t j, int64_t k) const { return (k * ny_ + j) * nx_ + i; }
  // The cell holding p, or -1 outside the grid.
  int64_t cell_of(const msg::Vec3& p) const;
  void flood(std::vector<int64_t> seeds);

  FreeSpaceBody body_;
  double cell_m_ = 0;
  msg::Vec3 origin_;  // the low corner of cell (0, 0, 0)
  int64_t nx_ = 0, ny_ = 0, nz_ = 1;
  std::vector<uint8_t> cells_;
  std::vector<bool> start_free_;
  size_t free_cells_ = 0, reachable_cells_ = 0;
};

}  // namespace scancrew::eval
