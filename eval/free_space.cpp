#include "eval/free_space.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/robot/body_model.hpp"

namespace scancrew::eval {

namespace {

constexpr double kGroundCellM = 0.2;
constexpr double kMultirotorCellM = 0.5;
constexpr int64_t kMaxCells = int64_t{1} << 31;

bool positive(double v) {
  return v > 0 && std::isfinite(v);
}

std::string check(const FreeSpaceBody& b, double cell_m) {
  std::ostringstream msg;
  if (!positive(b.radius_m))
    msg << "body radius_m must be positive, not " << b.radius_m;
  else if (!positive(cell_m))
    msg << "cell_m must be positive (or 0: the default), not " << cell_m;
  else if (b.kind == robot::RobotKind::kGround &&
           !(b.height_m > b.clearance_m && b.clearance_m >= 0))
    msg << "a ground body needs 0 <= clearance_m < height_m, not " << b.clearance_m << " and "
        << b.height_m;
  else if (b.kind == robot::RobotKind::kMultirotor &&
           !(b.min_altitude_m <= b.max_altitude_m && std::isfinite(b.min_altitude_m) &&
             std::isfinite(b.max_altitude_m)))
    msg << "the altitude band [" << b.min_altitude_m << ", " << b.max_altitude_m << "] m is empty";
  return msg.str();
}

}  // namespace

FreeSpaceBody default_body(robot::RobotKind kind) {
  const robot::BodyModel model = robot::BodyModel::of(kind);
  FreeSpaceBody body;
  body.kind = kind;
  body.radius_m = model.footprint_radius_m();
  if (kind == robot::RobotKind::kGround) {
    body.height_m = model.height_m;
    body.clearance_m = model.underside_m;
  } else {
    body.min_altitude_m = body.radius_m;
    body.max_altitude_m = 20.0;
  }
  return body;
}

Result<FreeSpace, std::string> FreeSpace::build(const sim::SceneSolids& solids,
                                                const sim::SceneSpec& scene,
                                                const FreeSpaceBody& body,
                                                const std::vector<msg::Vec3>& starts,
                                                const FreeSpaceOptions& options) {
  const bool ground = body.kind == robot::RobotKind::kGround;
  const double cell_m =
      options.cell_m != 0 ? options.cell_m : (ground ? kGroundCellM : kMultirotorCellM);
  if (std::string e = check(body, cell_m); !e.empty()) return make_unexpected("free space: " + e);
  if (starts.empty()) return make_unexpected(std::string("free space: no start positions"));
  const double sx = scene.max_m.x - scene.min_m.x, sy = scene.max_m.y - scene.min_m.y;
  if (!(sx > 0 && sy > 0)) return make_unexpected(std::string("free space: the bounds are empty"));

  FreeSpace fs;
  fs.body_ = body;
  fs.cell_m_ = cell_m;
  fs.nx_ = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(sx / cell_m - 1e-9)));
  fs.ny_ = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(sy / cell_m - 1e-9)));
  // z: cell k's centre is min_altitude + k cell_m, up to max_altitude
  fs.nz_ = ground ? 1
                  : static_cast<int64_t>(
                        std::floor((body.max_altitude_m - body.min_altitude_m) / cell_m + 1e-9)) +
                        1;
  fs.origin_ = {scene.min_m.x, scene.min_m.y, ground ? 0.0 : body.min_altitude_m - 0.5 * cell_m};
  const double cells =
      static_cast<double>(fs.nx_) * static_cast<double>(fs.ny_) * static_cast<double>(fs.nz_);
  if (cells > static_cast<double>(kMaxCells)) {
    std::ostringstream msg;
    msg << "free space: " << cells << " cells of " << cell_m << " m, more than " << kMaxCells
        << "; use a coarser cell_m";
    return make_unexpected(msg.str());
  }

  // which cells the body fits in
  const auto fits = [&](const msg::Vec3& p) {
    return ground
               ? !solids.cylinder_overlaps(p.x, p.y, body.radius_m, body.clearance_m, body.height_m)
               : !solids.sphere_overlaps(p, body.radius_m);
  };
  fs.cells_.assign(static_cast<size_t>(cells), kBlocked);
  const int64_t layer = fs.nx_ * fs.ny_;
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, layer * fs.nz_, 256), [&](const auto& range) {
    for (int64_t c = range.begin(); c != range.end(); ++c) {
      const int64_t k = c / layer, j = (c % layer) / fs.nx_, i = c % fs.nx_;
      if (fits(fs.cell_center(i, j, k))) fs.cells_[static_cast<size_t>(c)] = kFree;
    }
  });

  // seeds: a start's cell, or the free cells around it
  std::vector<int64_t> seeds;
  for (const msg::Vec3& s : starts) {
    msg::Vec3 p = s;
    if (ground)
      p.z = 0;
    else
      p.z = std::clamp(p.z, body.min_altitude_m, body.max_altitude_m);
    fs.start_free_.push_back(fits(p));
    const int64_t own = fs.cell_of(p);
    if (own >= 0 && fs.cells_[static_cast<size_t>(own)] == kFree) {
      seeds.push_back(own);
      continue;
    }
    const int64_t ci = static_cast<int64_t>(std::floor((p.x - fs.origin_.x) / cell_m));
    const int64_t cj = static_cast<int64_t>(std::floor((p.y - fs.origin_.y) / cell_m));
    const int64_t ck = ground ? 0 : static_cast<int64_t>(std::floor((p.z - fs.origin_.z) / cell_m));
    const int64_t dz = ground ? 0 : 1;
    for (int64_t k = ck - dz; k <= ck + dz; ++k)
      for (int64_t j = cj - 1; j <= cj + 1; ++j)
        for (int64_t i = ci - 1; i <= ci + 1; ++i)
          if (i >= 0 && j >= 0 && k >= 0 && i < fs.nx_ && j < fs.ny_ && k < fs.nz_ &&
              fs.cells_[static_cast<size_t>(fs.index(i, j, k))] == kFree)
            seeds.push_back(fs.index(i, j, k));
  }
  fs.flood(std::move(seeds));
  return fs;
}

// Breadth-first over free cells: 4-connected in a ground grid, 6-connected in a 3D one.
void FreeSpace::flood(std::vector<int64_t> queue) {
  for (const int64_t c : queue) cells_[static_cast<size_t>(c)] = kReachable;
  for (size_t head = 0; head < queue.size(); ++head) {
    const int64_t c = queue[head];
    const int64_t i = c % nx_, j = (c / nx_) % ny_, k = c / (nx_ * ny_);
    const int64_t next[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                                {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
    for (const auto& n : next) {
      if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= nx_ || n[1] >= ny_ || n[2] >= nz_) continue;
      const auto idx = static_cast<size_t>(index(n[0], n[1], n[2]));
      if (cells_[idx] != kFree) continue;
      cells_[idx] = kReachable;
      queue.push_back(static_cast<int64_t>(idx));
    }
  }
  // the starts' seeds may repeat: count the cells, not the queue
  reachable_cells_ = static_cast<size_t>(std::count(cells_.begin(), cells_.end(), kReachable));
  free_cells_ =
      reachable_cells_ + static_cast<size_t>(std::count(cells_.begin(), cells_.end(), kFree));
}

bool FreeSpace::start_free(size_t i) const {
  return i < start_free_.size() && start_free_[i];
}

bool FreeSpace::connected() const {
  return reachable_cells_ == free_cells_;
}

msg::Vec3 FreeSpace::cell_center(int64_t i, int64_t j, int64_t k) const {
  const auto at = [&](double o, int64_t n) { return o + (static_cast<double>(n) + 0.5) * cell_m_; };
  return {at(origin_.x, i), at(origin_.y, j),
          body_.kind == robot::RobotKind::kGround ? 0.0 : at(origin_.z, k)};
}

int64_t FreeSpace::cell_of(const msg::Vec3& p) const {
  const auto at = [&](double v, double o) {
    const double f = std::floor((v - o) / cell_m_);
    return std::isfinite(f) && std::abs(f) < 1e15 ? static_cast<int64_t>(f) : int64_t{-1};
  };
  const int64_t i = at(p.x, origin_.x), j = at(p.y, origin_.y);
  const int64_t k = body_.kind == robot::RobotKind::kGround ? 0 : at(p.z, origin_.z);
  if (i < 0 || j < 0 || k < 0 || i >= nx_ || j >= ny_ || k >= nz_) return -1;
  return index(i, j, k);
}

bool FreeSpace::reachable(const msg::Vec3& body_position) const {
  const int64_t c = cell_of(body_position);
  return c >= 0 && cells_[static_cast<size_t>(c)] == kReachable;
}

std::vector<msg::Vec3> FreeSpace::reachable_positions(double spacing_m) const {
  const int64_t step =
      std::max<int64_t>(1, static_cast<int64_t>(std::llround(spacing_m / cell_m_)));
  const int64_t step_z = body_.kind == robot::RobotKind::kGround ? 1 : step;
  std::vector<msg::Vec3> out;
  for (int64_t bk = 0; bk < nz_; bk += step_z)
    for (int64_t bj = 0; bj < ny_; bj += step)
      for (int64_t bi = 0; bi < nx_; bi += step) {
        // the reachable cell of the block nearest its centre (in cells, doubled: integers)
        int64_t best = -1, best_d2 = std::numeric_limits<int64_t>::max();
        for (int64_t k = bk; k < std::min(nz_, bk + step_z); ++k)
          for (int64_t j = bj; j < std::min(ny_, bj + step); ++j)
            for (int64_t i = bi; i < std::min(nx_, bi + step); ++i) {
              if (cells_[static_cast<size_t>(index(i, j, k))] != kReachable) continue;
              const int64_t di = 2 * (i - bi) - (step - 1), dj = 2 * (j - bj) - (step - 1),
                            dk = 2 * (k - bk) - (step_z - 1);
              const int64_t d2 = di * di + dj * dj + dk * dk;
              if (d2 < best_d2) {
                best_d2 = d2;
                best = index(i, j, k);
              }
            }
        if (best >= 0)
          out.push_back(cell_center(best % nx_, (best / nx_) % ny_, best / (nx_ * ny_)));
      }
  return out;
}

}  // namespace scancrew::eval
