#include "eval/reachable_truth.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numbers>
#include <sstream>
#include <utility>

#include "sim/mesh_io.hpp"

namespace scancrew::eval {

namespace {

using msg::Vec3;

// The observer with its half field of view as a tangent.
struct View {
  ObserverModel o;
  double tan_half;
  bool two_sided;  // a surface is seen from either side (the line of sight rules out solids')
};

// Whether a camera on a body at b, turned towards p, sees p (normal n) by range, field of
// view and facing; the camera's position in *cam.
bool in_view(const View& v, const Vec3& b, const Vec3& p, const Vec3& n, Vec3* cam) {
  const double dx = p.x - b.x, dy = p.y - b.y, hb = std::sqrt(dx * dx + dy * dy);
  const double h = hb - v.o.camera_forward_m;  // the depth, from the camera
  if (!(h >= v.o.min_range_m && h <= v.o.max_range_m) || hb <= 0) return false;
  const double f = v.o.camera_forward_m / hb;
  *cam = {b.x + f * dx, b.y + f * dy, b.z + v.o.camera_up_m};
  const Vec3 to_cam{cam->x - p.x, cam->y - p.y, cam->z - p.z};
  if (std::abs(to_cam.z) > h * v.tan_half) return false;
  double along = n.x * to_cam.x + n.y * to_cam.y + n.z * to_cam.z;
  if (v.two_sided) along = std::abs(along);
  if (!(along > 0)) return false;
  const double cos2 = v.o.min_facing_cos * v.o.min_facing_cos;
  return along * along > cos2 * (to_cam.x * to_cam.x + to_cam.y * to_cam.y + to_cam.z * to_cam.z);
}

// Whether a body at b may see some point within rho of c whose normal lies in the octant
// with signs s (conservative: in_view() decides).
bool may_view(const View& v, const Vec3& b, const Vec3& c, double rho, const double s[3]) {
  const double dx = c.x - b.x, dy = c.y - b.y, hb = std::sqrt(dx * dx + dy * dy);
  const double fwd = v.o.camera_forward_m;
  const double h_far = hb + rho - fwd;
  if (h_far < v.o.min_range_m || hb - rho - fwd > v.o.max_range_m) return false;
  const double dz = b.z + v.o.camera_up_m - c.z;
  if (std::abs(dz) - rho > std::min(h_far, v.o.max_range_m) * v.tan_half) return false;
  if (v.two_sided) return true;
  const double reach = rho + fwd;
  return s[0] * -dx > -reach || s[1] * -dy > -reach || s[2] * dz > -reach;
}

// Body positions bucketed in a uniform 3D grid, to list those near a point bucket.
class PoseGrid {
 public:
  PoseGrid(const std::vector<Vec3>& poses, double cell_xy_m, double cell_z_m)
      : cell_{cell_xy_m, cell_xy_m, cell_z_m} {
    lo_ = poses.front();
    Vec3 hi = lo_;
    for (const Vec3& p : poses) {
      lo_ = {std::min(lo_.x, p.x), std::min(lo_.y, p.y), std::min(lo_.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    n_ = {coord(hi.x, 0) + 1, coord(hi.y, 1) + 1, coord(hi.z, 2) + 1};
    std::vector<std::pair<int64_t, uint32_t>> keyed(poses.size());
    for (size_t i = 0; i < poses.size(); ++i)
      keyed[i] = {key(coord(poses[i].x, 0), coord(poses[i].y, 1), coord(poses[i].z, 2)),
                  static_cast<uint32_t>(i)};
    std::sort(keyed.begin(), keyed.end());
    offsets_.assign(static_cast<size_t>(n_[0] * n_[1] * n_[2]) + 1, 0);
    for (const auto& [k, i] : keyed) {
      ++offsets_[static_cast<size_t>(k) + 1];
      entries_.push_back(i);
    }
    for (size_t c = 1; c < offsets_.size(); ++c) offsets_[c] += offsets_[c - 1];
  }

  // Calls f(pose index) for the poses in the cells around c (one cell each way).
  template <class F>
  void near(const Vec3& c, F&& f) const {
    const int64_t ci[3] = {coord(c.x, 0), coord(c.y, 1), coord(c.z, 2)};
    for (int64_t k = std::max<int64_t>(0, ci[2] - 1); k <= std::min(n_[2] - 1, ci[2] + 1); ++k)
      for (int64_t j = std::max<int64_t>(0, ci[1] - 1); j <= std::min(n_[1] - 1, ci[1] + 1); ++j)
        for (int64_t i = std::max<int64_t>(0, ci[0] - 1); i <= std::min(n_[0] - 1, ci[0] + 1);
             ++i) {
          const auto cell = static_cast<size_t>(key(i, j, k));
          for (uint32_t e = offsets_[cell]; e < offsets_[cell + 1]; ++e) f(entries_[e]);
        }
  }

 private:
  int64_t coord(double v, int a) const {
    const double o = a == 0 ? lo_.x : (a == 1 ? lo_.y : lo_.z);
    return static_cast<int64_t>(std::floor((v - o) / cell_[a]));
  }
  int64_t key(int64_t i, int64_t j, int64_t k) const { return (k * n_[1] + j) * n_[0] + i; }

  double cell_[3];
  Vec3 lo_;
  std::array<int64_t, 3> n_{1, 1, 1};
  std::vector<uint32_t> offsets_, entries_;
};

// points sorted by (voxel, normal octant) into buckets
struct Buckets {
  std::array<float, 3> lo{};                         // the points' lower corner
  uint64_t nvx = 0, nvy = 0;                         // voxels along x and y
  std::vector<std::pair<uint64_t, uint32_t>> keyed;  // (voxel * 8 + octant, point index)
  std::vector<size_t> starts;  // each bucket's first entry in keyed, then keyed.size()
};

// sorts the points into buckets of side bm, by voxel and normal octant
Buckets make_buckets(const std::vector<std::array<float, 3>>& points,
                     const std::vector<std::array<float, 3>>& normals, double bm) {
  Buckets out;
  std::array<float, 3>& lo = out.lo;
  lo = points.front();
  std::array<float, 3> hi = lo;
  for (const auto& p : points)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  const auto vox = [&](const std::array<float, 3>& p, int a) {
    return static_cast<uint64_t>(std::floor((p[a] - lo[a]) / bm));
  };
  const uint64_t nvx = vox(hi, 0) + 1, nvy = vox(hi, 1) + 1;
  out.nvx = nvx;
  out.nvy = nvy;
  std::vector<std::pair<uint64_t, uint32_t>>& keyed = out.keyed;
  keyed.resize(points.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto& n = normals[i];
      const uint64_t oct = (n[0] < 0 ? 1U : 0U) | (n[1] < 0 ? 2U : 0U) | (n[2] < 0 ? 4U : 0U);
      const uint64_t v = (vox(points[i], 2) * nvy + vox(points[i], 1)) * nvx + vox(points[i], 0);
      keyed[i] = {v * 8 + oct, static_cast<uint32_t>(i)};
    }
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());
  for (size_t i = 0; i < keyed.size(); ++i)
    if (i == 0 || keyed[i].first != keyed[i - 1].first) out.starts.push_back(i);
  out.starts.push_back(keyed.size());
  return out;
}

// casts lines of sight from candidate body positions to a bucket's points
struct RayCaster {
  const View& view;
  const std::vector<Vec3>& poses;
  const sim::SceneSolids& solids;
  double end_margin_m;
  int cap, near_cap;

  // whether point p (normal n) is seen from one of cands ((distance, pose), nearest first);
  // last: the candidate that served the bucket's last observable point (updated); counts
  // the lines of sight cast into rays
  bool observable(const std::vector<std::pair<double, uint32_t>>& cands, const Vec3& p,
                  const Vec3& n, int64_t& last, uint64_t& rays) const {
    Vec3 cam;
    // the candidate that served the bucket's last point first
    if (last >= 0 && in_view(view, poses[cands[static_cast<size_t>(last)].second], p, n, &cam)) {
      ++rays;
      if (!solids.segment_blocked(cam, p, end_margin_m)) return true;
    }
    // the nearest candidates first; after near_cap lines of sight, the others in a
    // spread order (every stride-th, then the next phase), up to cap in all
    int cast = 0;
    const auto try_candidate = [&](size_t k) {
      if (static_cast<int64_t>(k) == last) return false;
      const bool ok = in_view(view, poses[cands[k].second], p, n, &cam);
      if (!ok) return false;
      ++cast;
      ++rays;
      if (solids.segment_blocked(cam, p, end_margin_m)) return false;
      last = static_cast<int64_t>(k);
      return true;
    };
    bool found = false;
    size_t k = 0;
    for (; k < cands.size() && cast < near_cap && !found; ++k) found = try_candidate(k);
    const size_t rest = cands.size() - k;
    const size_t stride = std::max<size_t>(1, rest / static_cast<size_t>(cap - near_cap + 1));
    for (size_t phase = 0; phase < stride && !found && cast < cap; ++phase)
      for (size_t j = k + phase; j < cands.size() && !found && cast < cap; j += stride)
        found = try_candidate(j);
    return found;
  }
};

std::string check(const ObserverModel& o, const ReachableTruthOptions& opt) {
  std::ostringstream msg;
  if (!(o.min_range_m >= 0 && o.max_range_m > o.min_range_m && std::isfinite(o.max_range_m)))
    msg << "the range must satisfy 0 <= min_range_m < max_range_m, not [" << o.min_range_m << ", "
        << o.max_range_m << "]";
  else if (!(o.fov_v_deg > 0 && o.fov_v_deg < 180))
    msg << "fov_v_deg must be in (0, 180), not " << o.fov_v_deg;
  else if (!(o.min_facing_cos >= 0 && o.min_facing_cos < 1))
    msg << "min_facing_cos must be in [0, 1), not " << o.min_facing_cos;
  else if (!(opt.pose_spacing_m >= 0 && opt.bucket_m > 0 && opt.max_rays_per_point > 0 &&
             opt.end_margin_m >= 0))
    msg << "pose_spacing_m >= 0, bucket_m > 0, max_rays_per_point > 0, end_margin_m >= 0";
  return msg.str();
}

}  // namespace

ObserverModel observer_from_camera(const sim::CameraSpec& camera) {
  return {.camera_forward_m = camera.mount_forward_m,
          .camera_up_m = camera.mount_up_m,
          .min_range_m = camera.min_range_m,
          .max_range_m = camera.max_range_m,
          .fov_v_deg = camera.fov_v_deg};
}

Result<ReachableTruth, std::string> reachable_truth(
    const std::vector<std::array<float, 3>>& points,
    const std::vector<std::array<float, 3>>& normals, const sim::SceneSolids& solids,
    const FreeSpace& free_space, const ObserverModel& observer,
    const ReachableTruthOptions& options) {
  if (points.size() != normals.size())
    return make_unexpected(std::string("reachable truth: points and normals differ in length"));
  if (std::string e = check(observer, options); !e.empty())
    return make_unexpected("reachable truth: " + e);
  const bool ground = free_space.body().kind == robot::RobotKind::kGround;
  const double spacing = options.pose_spacing_m > 0 ? options.pose_spacing_m : (ground ? 0.5 : 1.0);
  const std::vector<Vec3> poses = free_space.reachable_positions(spacing);
  if (poses.empty())
    return make_unexpected(std::string("reachable truth: no reachable body position"));
  ReachableTruth out;
  out.observable.assign(points.size(), 0);
  out.poses = poses.size();
  if (points.empty()) return out;

  const View view{observer, std::tan(0.5 * observer.fov_v_deg * std::numbers::pi / 180),
                  !options.trust_normals};
  const double bm = options.bucket_m, rho = 0.5 * std::sqrt(3.0) * bm;
  const double reach_xy = observer.max_range_m + observer.camera_forward_m + rho;
  const double reach_z = reach_xy * view.tan_half + std::abs(observer.camera_up_m) + rho;
  const PoseGrid grid(poses, reach_xy, reach_z);

  // buckets: points sorted by (voxel, normal octant)
  const Buckets buckets = make_buckets(points, normals, bm);
  const std::array<float, 3>& lo = buckets.lo;
  const uint64_t nvx = buckets.nvx, nvy = buckets.nvy;
  const std::vector<std::pair<uint64_t, uint32_t>>& keyed = buckets.keyed;
  const std::vector<size_t>& starts = buckets.starts;
  out.buckets = starts.size() - 1;

  std::atomic<uint64_t> rays{0};
  const int cap = options.max_rays_per_point, near_cap = (cap + 1) / 2;
  const RayCaster caster{view, poses, solids, options.end_margin_m, cap, near_cap};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, out.buckets, 4), [&](const auto& r) {
    std::vector<std::pair<double, uint32_t>> cands;  // (distance, pose), nearest first
    uint64_t local_rays = 0;
    for (size_t b = r.begin(); b != r.end(); ++b) {
      // the bucket's voxel, octant and candidate body positions
      const uint64_t key = keyed[starts[b]].first, v = key / 8, oct = key % 8;
      const uint64_t ix = v % nvx, iy = (v / nvx) % nvy, iz = v / (nvx * nvy);
      const Vec3 c{lo[0] + (static_cast<double>(ix) + 0.5) * bm,
                   lo[1] + (static_cast<double>(iy) + 0.5) * bm,
                   lo[2] + (static_cast<double>(iz) + 0.5) * bm};
      const double s[3] = {(oct & 1U) != 0 ? -1.0 : 1.0, (oct & 2U) != 0 ? -1.0 : 1.0,
                           (oct & 4U) != 0 ? -1.0 : 1.0};
      cands.clear();
      grid.near(c, [&](uint32_t i) {
        const Vec3& p = poses[i];
        if (!may_view(view, p, c, rho, s)) return;
        const double dx = p.x - c.x, dy = p.y - c.y, dz = p.z + observer.camera_up_m - c.z;
        cands.emplace_back(dx * dx + dy * dy + dz * dz, i);
      });
      if (cands.empty()) continue;
      std::sort(cands.begin(), cands.end());
      int64_t last = -1;  // the candidate that served the bucket's last observable point
      for (size_t e = starts[b]; e < starts[b + 1]; ++e) {
        const uint32_t pi = keyed[e].second;
        const Vec3 p{points[pi][0], points[pi][1], points[pi][2]};
        const Vec3 n{normals[pi][0], normals[pi][1], normals[pi][2]};
        if (caster.observable(cands, p, n, last, local_rays)) out.observable[pi] = 1;
      }
    }
    rays += local_rays;
  });
  out.rays = rays;
  out.observable_count =
      static_cast<size_t>(std::count(out.observable.begin(), out.observable.end(), 1));
  return out;
}

sim::SurfaceSamples observable_samples(const sim::SurfaceSamples& truth,
                                       const std::vector<uint8_t>& observable) {
  sim::SurfaceSamples out;
  for (size_t i = 0; i < truth.points.size() && i < observable.size(); ++i)
    if (observable[i] != 0) {
      out.points.push_back(truth.points[i]);
      out.normals.push_back(truth.normals[i]);
    }
  if (!truth.points.empty())
    out.area_m2 = truth.area_m2 * static_cast<double>(out.points.size()) /
                  static_cast<double>(truth.points.size());
  return out;
}

Result<SceneReachableTruth, std::string> scene_reachable_truth(
    const std::string& scene_path, const FreeSpaceBody& body, const std::vector<msg::Vec3>& starts,
    const sim::CameraSpec& camera, const sim::SamplingOptions& sampling,
    const ReachableTruthOptions& options) {
  auto scene = sim::load_scene(scene_path);
  if (!scene) return make_unexpected(scene.error().front());
  auto meshes = sim::load_scene_meshes(*scene);
  if (!meshes) return make_unexpected(meshes.error());
  auto truth = sim::sample_surfaces(*scene, *meshes, sampling);
  if (!truth) return make_unexpected(truth.error());
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const sim::SceneSolids solids(*scene, *meshes);
  auto free_space = FreeSpace::build(solids, *scene, body, starts);
  if (!free_space) return make_unexpected(free_space.error());
  const auto t1 = Clock::now();
  auto reachable = reachable_truth(truth->points, truth->normals, solids, *free_space,
                                   observer_from_camera(camera), options);
  if (!reachable) return make_unexpected(reachable.error());
  const auto t2 = Clock::now();
  SceneReachableTruth out{.truth = std::move(truth).value(),
                          .reachable = std::move(reachable).value(),
                          .free_cells = free_space->free_cells(),
                          .reachable_cells = free_space->reachable_cells()};
  for (size_t i = 0; i < starts.size(); ++i) out.start_free.push_back(free_space->start_free(i));
  out.seconds_free_space = std::chrono::duration<double>(t1 - t0).count();
  out.seconds_rays = std::chrono::duration<double>(t2 - t1).count();
  return out;
}

Result<SceneReachableTruth, std::string> scene_reachable_truth(
    const std::string& scene_path, robot::RobotKind kind, const std::vector<msg::Vec3>& starts,
    const sim::SamplingOptions& sampling) {
  return scene_reachable_truth(scene_path, default_body(kind), starts, sim::CameraSpec{}, sampling);
}

}  // namespace scancrew::eval
