#include "core/tsdf/integrator.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace scancrew::tsdf {

namespace {

constexpr size_t kNoPixel = std::numeric_limits<size_t>::max();

bool rigid(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) return false;
  const Eigen::Matrix3d rotation = T.linear();
  return (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <
             1e-6 &&
         std::abs(rotation.determinant() - 1.0) < 1e-6;
}

// Negative depths (−inf too) are refused; NaN is the "no measurement" marker and +inf
// "no return within the sensor's range" (REP 117).
bool bad_depth(float d) {
  return d < 0;
}

constexpr float kBeyondRange = std::numeric_limits<float>::infinity();
// A pinhole depth camera's half field of view has a tangent below this (169 deg across).
constexpr double kMaxHalfFovTan = 10;
// Maps are of places: no camera is this far from the map's origin.
constexpr double kMaxCameraDistanceM = 1e6;

// Everything but the pixels.
std::string check_header(const DepthFrame& f) {
  if (f.width == 0 || f.height == 0 || f.depth_m == nullptr) return "empty depth image";
  if (f.size != static_cast<size_t>(f.width) * f.height)
    return "depth has " + std::to_string(f.size) + " values for a " + std::to_string(f.width) +
           "x" + std::to_string(f.height) + " image";
  if (!(std::isfinite(f.fx) && f.fx > 0 && std::isfinite(f.fy) && f.fy > 0 && std::isfinite(f.cx) &&
        std::isfinite(f.cy)))
    return "intrinsics not finite and positive";
  // the frustum's box is what is allocated (a block bitmap): a focal length of 1e-3 px asked
  // for 1e14 bytes, a camera at 1e12 m overflowed the block indices
  if (f.cx < 0 || f.cx > f.width || f.cy < 0 || f.cy > f.height)
    return "principal point outside the image";
  if (std::max(f.cx, f.width - f.cx) > kMaxHalfFovTan * f.fx ||
      std::max(f.cy, f.height - f.cy) > kMaxHalfFovTan * f.fy)
    return "focal length too short: a field of view over 2 atan(10) = 169 deg";
  if (!rigid(f.T_world_cam)) return "camera pose is not a rigid transform";
  if (f.T_world_cam.translation().cwiseAbs().maxCoeff() > kMaxCameraDistanceM)
    return "camera more than 1000 km from the map's origin";
  return {};
}

std::string bad_pixel_message(const DepthFrame& f, size_t i) {
  return "depth value " + std::to_string(f.depth_m[i]) + " at pixel " +
         std::to_string(i % f.width) + ", " + std::to_string(i / f.width) +
         " (NaN marks no measurement, +inf no return within range; negative values are refused)";
}

}  // namespace

std::string check_frame(const DepthFrame& f) {
  if (auto problem = check_header(f); !problem.empty()) return problem;
  for (size_t i = 0; i < f.size; ++i)
    if (bad_depth(f.depth_m[i])) return bad_pixel_message(f, i);
  return {};
}

// 1. One read of the image, split by tile rows across the cores: each tile's farthest depth
//    within range, and the first bad pixel (the frame is refused before anything is written).
std::string Integrator::scan_tiles(const DepthFrame& f) {
  const int tp = config_.tile_px;
  tiles_x_ = (static_cast<int>(f.width) + tp - 1) / tp;
  tiles_y_ = (static_cast<int>(f.height) + tp - 1) / tp;
  tile_max_.assign(static_cast<size_t>(tiles_x_) * tiles_y_, -1.0f);
  first_bad_.assign(static_cast<size_t>(tiles_y_), kNoPixel);
  const auto min_r = static_cast<float>(config_.min_range_m);
  const auto max_r = static_cast<float>(config_.max_range_m);
  // a clearing ray writes up to max_r − μ along the axis
  const float clear_r = config_.clear_beyond_range
                            ? static_cast<float>(config_.max_range_m - config_.truncation_m)
                            : -1.0f;
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_y_), [&](const tbb::blocked_range<int>& r) {
    for (int ty = r.begin(); ty != r.end(); ++ty) {
      float* tiles = tile_max_.data() + static_cast<size_t>(ty) * tiles_x_;
      const auto v_end = std::min<uint32_t>(f.height, static_cast<uint32_t>((ty + 1) * tp));
      for (auto v = static_cast<uint32_t>(ty * tp); v < v_end; ++v) {
        const float* row = f.depth_m + static_cast<size_t>(v) * f.width;
        bool bad = false;
        for (int tx = 0; tx < tiles_x_; ++tx) {
          const auto u_end = std::min<uint32_t>(f.width, static_cast<uint32_t>((tx + 1) * tp));
          float m = tiles[tx];
          for (auto u = static_cast<uint32_t>(tx * tp); u < u_end; ++u) {
            const float d = row[u];
            bad |= bad_depth(d);
            m = (d >= min_r && d <= max_r) ? std::max(m, d) : m;  // false for NaN
            m = d == kBeyondRange ? std::max(m, clear_r) : m;
          }
          tiles[tx] = m;
        }
        if (bad) {
          for (uint32_t u = 0; u < f.width; ++u)
            if (bad_depth(row[u])) {
              first_bad_[static_cast<size_t>(ty)] = static_cast<size_t>(v) * f.width + u;
              break;
            }
          break;
        }
      }
    }
  });
  for (size_t i : first_bad_)
    if (i != kNoPixel) return bad_pixel_message(f, i);
  return {};
}

// 2. Candidate blocks: those of the frustum's bounding box whose voxel centres can be written.
//    The box of the block's voxel centres, in the camera frame, gives a depth interval
//    [z_min, z_max] and an image footprint; some tile under the footprint must see at least
//    to z_min − μ (a voxel is written when it lies in front of the measured surface or less
//    than μ behind it). Rows of blocks are tested in parallel; the order stays fixed.
void Integrator::select_blocks(const DepthFrame& f, float frame_max) {
  const double s = config_.voxel_m;
  const double block_m = s * kBlockSide;
  const double mu = config_.truncation_m;
  const double reach = frame_max + mu;
  const Eigen::Isometry3d T_cam_world = f.T_world_cam.inverse();
  Eigen::Vector3d lo = f.T_world_cam.translation(), hi = lo;
  for (double u : {0.0, static_cast<double>(f.width)})
    for (double v : {0.0, static_cast<double>(f.height)}) {
      const Eigen::Vector3d p = f.T_world_cam * Eigen::Vector3d((u - f.cx) / f.fx * reach,
                                                                (v - f.cy) / f.fy * reach, reach);
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  const Eigen::Vector3i b_lo = (lo / block_m).array().floor().cast<int>();
  const Eigen::Vector3i b_hi = (hi / block_m).array().floor().cast<int>();
  const Eigen::Vector3i n = b_hi - b_lo + Eigen::Vector3i::Ones();
  // half extents, in the camera frame, of the box around a block's voxel centres
  const Eigen::Vector3d extent =
      T_cam_world.linear().cwiseAbs() * Eigen::Vector3d::Constant(0.5 * (kBlockSide - 1) * s);
  const int tp = config_.tile_px;
  selected_.assign(static_cast<size_t>(n.x()) * n.y() * n.z(), 0);

  auto test = [&](const Eigen::Vector3i& b) -> bool {
    const Eigen::Vector3d c =
        T_cam_world * ((b.cast<double>() + Eigen::Vector3d::Constant(0.5)) * block_m);
    const double z_min = c.z() - extent.z(), z_max = c.z() + extent.z();
    if (z_max <= 0 || z_min > reach) return false;
    int u0 = 0, u1 = tiles_x_ - 1, v0 = 0, v1 = tiles_y_ - 1;
    if (z_min > 1e-3) {
      // x/z over the box [c ± extent] is extreme at its corners
      const double x0 = c.x() - extent.x(), x1 = c.x() + extent.x();
      const double y0 = c.y() - extent.y(), y1 = c.y() + extent.y();
      const double umin = f.fx * std::min(x0 / z_min, x0 / z_max) + f.cx + 0.5;
      const double umax = f.fx * std::max(x1 / z_min, x1 / z_max) + f.cx + 0.5;
      const double vmin = f.fy * std::min(y0 / z_min, y0 / z_max) + f.cy + 0.5;
      const double vmax = f.fy * std::max(y1 / z_min, y1 / z_max) + f.cy + 0.5;
      if (umax < 0 || vmax < 0 || umin >= f.width || vmin >= f.height) return false;
      u0 = std::max(0, static_cast<int>(std::floor(umin)) / tp);
      u1 = std::min(tiles_x_ - 1, static_cast<int>(std::floor(umax)) / tp);
      v0 = std::max(0, static_cast<int>(std::floor(vmin)) / tp);
      v1 = std::min(tiles_y_ - 1, static_cast<int>(std::floor(vmax)) / tp);
    }
    const auto needed = static_cast<float>(z_min - mu);
    for (int ty = v0; ty <= v1; ++ty) {
      const float* tiles = tile_max_.data() + static_cast<size_t>(ty) * tiles_x_;
      for (int tx = u0; tx <= u1; ++tx)
        if (tiles[tx] >= needed) return true;
    }
    return false;
  };
  const int rows = n.y() * n.z();
  tbb::parallel_for(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& r) {
    for (int row = r.begin(); row != r.end(); ++row) {
      const int by = b_lo.y() + row % n.y(), bz = b_lo.z() + row / n.y();
      uint8_t* flags = selected_.data() + static_cast<size_t>(row) * n.x();
      for (int i = 0; i < n.x(); ++i) flags[i] = test({b_lo.x() + i, by, bz}) ? 1 : 0;
    }
  });
  candidates_.clear();
  for (int row = 0; row < rows; ++row) {
    const uint8_t* flags = selected_.data() + static_cast<size_t>(row) * n.x();
    for (int i = 0; i < n.x(); ++i)
      if (flags[i] != 0)
        candidates_.emplace_back(b_lo.x() + i, b_lo.y() + row % n.y(), b_lo.z() + row / n.y());
  }
}

// makes the candidate blocks writable (allocated, or copied away from snapshots) as work_
void Integrator::touch_blocks(TsdfMap& map) {
  work_.resize(candidates_.size());
  for (size_t i = 0; i < candidates_.size(); ++i) {
    BlockWork& bw = work_[i];
    bw.index = candidates_[i];
    bw.fresh = map.find(candidates_[i]) == nullptr;
    bw.block = &map.touch(candidates_[i]);
    bw.updated = 0;
  }
}

// integrates the frame into the work_ blocks in parallel, marking the updated ones with sequence
void Integrator::integrate_blocks(const DepthFrame& f, uint64_t sequence) {
  const Eigen::Isometry3f T_cam_world = f.T_world_cam.inverse().cast<float>();
  const Eigen::Matrix3f rotation = T_cam_world.linear();
  const Eigen::Vector3f t = T_cam_world.translation();
  const auto s = static_cast<float>(config_.voxel_m);
  const auto fx = static_cast<float>(f.fx), fy = static_cast<float>(f.fy);
  // + 0.5: the pixel is floor(projection + 0.5), a truncation once the range is checked
  const auto cx = static_cast<float>(f.cx) + 0.5f, cy = static_cast<float>(f.cy) + 0.5f;
  const auto min_r = static_cast<float>(config_.min_range_m);
  const auto max_r = static_cast<float>(config_.max_range_m);
  const auto mu = static_cast<float>(config_.truncation_m);
  const bool clear = config_.clear_beyond_range;
  const float clear_r = max_r - mu;
  const auto w_max = static_cast<float>(config_.max_weight);
  const bool inverse_square = config_.weight == TsdfWeight::kInverseSquare;
  const auto width = static_cast<float>(f.width), height = static_cast<float>(f.height);
  const Eigen::Vector3f dx = rotation.col(0) * s, dy = rotation.col(1) * s,
                        dz = rotation.col(2) * s;

  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, work_.size(), 2), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          BlockWork& bw = work_[i];
          const Eigen::Vector3f origin =
              rotation *
                  (((bw.index * kBlockSide).cast<float>() + Eigen::Vector3f::Constant(0.5f)) * s) +
              t;
          uint32_t updated = 0;
          Voxel* voxel = bw.block->voxels.data();
          for (int z = 0; z < kBlockSide; ++z)
            for (int y = 0; y < kBlockSide; ++y) {
              Eigen::Vector3f p = origin + static_cast<float>(y) * dy + static_cast<float>(z) * dz;
              for (int x = 0; x < kBlockSide; ++x, p += dx, ++voxel) {
                const float pz = p.z();
                if (pz <= 0) continue;
                const float inv_z = 1.0f / pz;
                const float uf = fx * p.x() * inv_z + cx;
                const float vf = fy * p.y() * inv_z + cy;
                if (!(uf >= 0 && vf >= 0 && uf < width && vf < height)) continue;
                const float depth = f.depth_m[static_cast<size_t>(static_cast<int>(vf)) * f.width +
                                              static_cast<size_t>(static_cast<int>(uf))];
                float d_axis = 0;
                if (depth >= min_r && depth <= max_r) {
                  // thesis 1.3.3: d along the viewing ray, |p|/z times the difference along
                  // the optical axis (≥ it), so the axis difference decides the clear cases
                  d_axis = depth - pz;
                } else if (clear && depth == kBeyondRange && pz <= clear_r) {
                  d_axis = mu;  // the surface lies beyond max_r: at least μ ahead of p
                } else {
                  continue;
                }
                if (d_axis < -mu) continue;
                const float squared_norm = p.squaredNorm();
                const float phi =
                    d_axis >= mu ? mu : std::min(d_axis * std::sqrt(squared_norm) * inv_z, mu);
                if (phi < -mu) continue;
                const float wc = inverse_square ? 1.0f / squared_norm : 1.0f;
                const float w = voxel->weight + wc;
                voxel->distance_m = (voxel->distance_m * voxel->weight + phi * wc) / w;
                voxel->weight = std::min(w, w_max);
                ++updated;
              }
            }
          bw.updated = updated;
          if (updated > 0) bw.block->modified = sequence;
        }
      });
}

Result<IntegrationStats, std::string> Integrator::integrate(TsdfMap& map, const DepthFrame& f) {
  if (auto problem = check_header(f); !problem.empty()) return make_unexpected(problem);
  if (map.config().voxel_m != config_.voxel_m)
    return make_unexpected(std::string("integrator and map have different voxel sizes"));
  if (auto problem = scan_tiles(f); !problem.empty()) return make_unexpected(problem);
  IntegrationStats stats;
  const float frame_max = *std::max_element(tile_max_.begin(), tile_max_.end());
  if (frame_max < 0) return stats;
  select_blocks(f, frame_max);
  stats.candidate_blocks = candidates_.size();

  // 3. blocks writable (allocated, or copied away from snapshots), then integrated in parallel
  const uint64_t sequence = map.begin_update();
  touch_blocks(map);
  integrate_blocks(f, sequence);

  for (const BlockWork& bw : work_) {
    if (bw.updated == 0) {
      if (bw.fresh) map.erase(bw.index);
      continue;
    }
    ++stats.updated_blocks;
    stats.new_blocks += bw.fresh ? 1 : 0;
    stats.updated_voxels += bw.updated;
  }
  return stats;
}

}  // namespace scancrew::tsdf
