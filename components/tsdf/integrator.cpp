#include "components/tsdf/integrator.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace scancrew::tsdf {

namespace {

bool rigid(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) return false;
  const Eigen::Matrix3d rotation = T.linear();
  return (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <
             1e-6 &&
         std::abs(rotation.determinant() - 1.0) < 1e-6;
}

struct BlockWork {
  Block* block = nullptr;
  BlockIndex index;
  bool fresh = false;
  uint32_t updated = 0;
};

}  // namespace

std::string check_frame(const DepthFrame& f) {
  if (f.width == 0 || f.height == 0 || f.depth_m == nullptr) return "empty depth image";
  if (f.size != static_cast<size_t>(f.width) * f.height)
    return "depth has " + std::to_string(f.size) + " values for a " + std::to_string(f.width) +
           "x" + std::to_string(f.height) + " image";
  if (!(std::isfinite(f.fx) && f.fx > 0 && std::isfinite(f.fy) && f.fy > 0 && std::isfinite(f.cx) &&
        std::isfinite(f.cy)))
    return "intrinsics not finite and positive";
  if (!rigid(f.T_world_cam)) return "camera pose is not a rigid transform";
  for (size_t i = 0; i < f.size; ++i) {
    const float d = f.depth_m[i];
    if (std::isinf(d) || d < 0)
      return "depth value " + std::to_string(d) + " at pixel " + std::to_string(i % f.width) +
             ", " + std::to_string(i / f.width) +
             " (NaN marks no measurement; inf and negative are refused)";
  }
  return {};
}

Result<IntegrationStats, std::string> Integrator::integrate(TsdfMap& map, const DepthFrame& f) {
  if (auto problem = check_frame(f); !problem.empty()) return make_unexpected(problem);
  if (map.config().voxel_m != config_.voxel_m)
    return make_unexpected(std::string("integrator and map have different voxel sizes"));
  IntegrationStats stats;
  const auto min_r = static_cast<float>(config_.min_range_m);
  const auto max_r = static_cast<float>(config_.max_range_m);
  const auto mu = static_cast<float>(config_.truncation_m);

  // 1. tiles: the farthest valid depth under each
  const int tp = config_.tile_px;
  const int tiles_x = (static_cast<int>(f.width) + tp - 1) / tp;
  const int tiles_y = (static_cast<int>(f.height) + tp - 1) / tp;
  tile_max_.assign(static_cast<size_t>(tiles_x) * tiles_y, -1.0f);
  float frame_max = -1;
  for (uint32_t v = 0; v < f.height; ++v) {
    const float* row = f.depth_m + static_cast<size_t>(v) * f.width;
    float* tiles = tile_max_.data() + static_cast<size_t>(v / tp) * tiles_x;
    for (uint32_t u = 0; u < f.width; ++u) {
      const float d = row[u];
      if (d >= min_r && d <= max_r) {
        float& t = tiles[u / tp];
        t = std::max(t, d);
        frame_max = std::max(frame_max, d);
      }
    }
  }
  if (frame_max < 0) return stats;

  // 2. candidate blocks: the frustum's bounding box, tested against the tiles
  const double block_m = config_.voxel_m * kBlockSide;
  const double reach = frame_max + config_.truncation_m;
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
  const double radius = block_m * std::sqrt(3.0) / 2;
  candidates_.clear();
  for (int bz = b_lo.z(); bz <= b_hi.z(); ++bz)
    for (int by = b_lo.y(); by <= b_hi.y(); ++by)
      for (int bx = b_lo.x(); bx <= b_hi.x(); ++bx) {
        const Eigen::Vector3d c =
            T_cam_world *
            ((Eigen::Vector3d(bx, by, bz) + Eigen::Vector3d::Constant(0.5)) * block_m);
        const double near = c.z() - radius;
        if (c.z() + radius <= 0 || near > reach) continue;
        int u0 = 0, u1 = tiles_x - 1, v0 = 0, v1 = tiles_y - 1;
        if (near > 1e-3) {
          // x/z over the box [c ± r] is extreme at its corners
          const double zn = near, zf = c.z() + radius;
          const double umin = f.fx * std::min((c.x() - radius) / zn, (c.x() - radius) / zf) + f.cx;
          const double umax = f.fx * std::max((c.x() + radius) / zn, (c.x() + radius) / zf) + f.cx;
          const double vmin = f.fy * std::min((c.y() - radius) / zn, (c.y() - radius) / zf) + f.cy;
          const double vmax = f.fy * std::max((c.y() + radius) / zn, (c.y() + radius) / zf) + f.cy;
          if (umax < -0.5 || vmax < -0.5 || umin > f.width - 0.5 || vmin > f.height - 0.5) continue;
          u0 = std::max(0, static_cast<int>(std::floor(umin + 0.5)) / tp);
          u1 = std::min(tiles_x - 1, static_cast<int>(std::floor(umax + 0.5)) / tp);
          v0 = std::max(0, static_cast<int>(std::floor(vmin + 0.5)) / tp);
          v1 = std::min(tiles_y - 1, static_cast<int>(std::floor(vmax + 0.5)) / tp);
        }
        const auto needed = static_cast<float>(near - config_.truncation_m);
        bool seen = false;
        for (int ty = v0; ty <= v1 && !seen; ++ty)
          for (int tx = u0; tx <= u1 && !seen; ++tx)
            seen = tile_max_[static_cast<size_t>(ty) * tiles_x + tx] >= needed;
        if (seen) candidates_.emplace_back(bx, by, bz);
      }
  stats.candidate_blocks = candidates_.size();

  // 3. blocks writable (allocated, or copied away from snapshots), then integrated in parallel
  const uint64_t sequence = map.begin_update();
  std::vector<BlockWork> work(candidates_.size());
  for (size_t i = 0; i < candidates_.size(); ++i) {
    work[i].index = candidates_[i];
    work[i].fresh = map.find(candidates_[i]) == nullptr;
    work[i].block = &map.touch(candidates_[i]);
  }
  const Eigen::Matrix3f rotation = T_cam_world.linear().cast<float>();
  const Eigen::Vector3f t = T_cam_world.translation().cast<float>();
  const auto s = static_cast<float>(config_.voxel_m);
  const auto fx = static_cast<float>(f.fx), fy = static_cast<float>(f.fy);
  const auto cx = static_cast<float>(f.cx), cy = static_cast<float>(f.cy);
  const auto w_max = static_cast<float>(config_.max_weight);
  const bool inverse_square = config_.weight == "inverse_square";
  const auto width = static_cast<int>(f.width), height = static_cast<int>(f.height);
  const Eigen::Vector3f dx = rotation.col(0) * s;

  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, work.size(), 2), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          BlockWork& bw = work[i];
          const Eigen::Vector3f origin =
              ((bw.index * kBlockSide).cast<float>() + Eigen::Vector3f::Constant(0.5f)) * s;
          uint32_t updated = 0;
          for (int z = 0; z < kBlockSide; ++z)
            for (int y = 0; y < kBlockSide; ++y) {
              Eigen::Vector3f p = rotation * (origin + Eigen::Vector3f(0, static_cast<float>(y) * s,
                                                                       static_cast<float>(z) * s)) +
                                  t;
              Voxel* voxel = &bw.block->at(0, y, z);
              for (int x = 0; x < kBlockSide; ++x, p += dx, ++voxel) {
                if (p.z() <= 0) continue;
                const float inv_z = 1.0f / p.z();
                const auto u = static_cast<int>(std::floor(fx * p.x() * inv_z + cx + 0.5f));
                const auto v = static_cast<int>(std::floor(fy * p.y() * inv_z + cy + 0.5f));
                if (u < 0 || v < 0 || u >= width || v >= height) continue;
                const float depth = f.depth_m[static_cast<size_t>(v) * f.width + u];
                if (!(depth >= min_r && depth <= max_r)) continue;
                const float d = depth - p.z();
                if (d < -mu) continue;
                const float phi = std::min(d, mu);
                const float wc = inverse_square ? 1.0f / p.squaredNorm() : 1.0f;
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

  for (const BlockWork& bw : work) {
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
