// TsdfMapper's drift between robots (align_teammates; tsdf_mapper.hpp and docs/mapping.md,
// "Drift between robots"): teammates' patches registered onto this robot's own, fused through
// the correction found.

#include <algorithm>
#include <cmath>
#include <vector>

#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "core/tsdf/patch_fusion.hpp"
#include "core/tsdf/patch_transform.hpp"
#include "core/tsdf/sdf_registration.hpp"
#include "executors/log.hpp"

namespace scancrew::tsdf_mapper {

namespace {

// a teammate's latest patches registered together (about 5 s of its images at 10 Hz): enough
// surface to constrain x, y, z and yaw, recent enough to share one drift
constexpr size_t kRecentPatches = 10;
// registered again after this many new patches of it
constexpr uint32_t kRegisterEvery = 5;
// samples per registration at most (a fixed stride over the patches' near-surface voxels)
constexpr size_t kMaxSamples = 8000;
// a new correction is adopted when it brings the residual under this share of the current
constexpr double kMinImprovement = 0.7;
// and under this share of the truncation distance μ
constexpr double kAgreement = 0.25;

// The near-surface voxels (|φ| < μ/2, known) of the patches, every stride-th.
std::vector<tsdf::SdfSample> samples_of(const std::deque<tsdf::DecodedPatch>& patches,
                                        const tsdf::TsdfConfig& config) {
  const auto w_th = static_cast<float>(config.w_th);
  const double band = 0.5 * config.truncation_m;
  const auto near = [&](const tsdf::Voxel& v) {
    return v.weight >= w_th && std::abs(v.distance_m) < band;
  };
  size_t count = 0;
  for (const tsdf::DecodedPatch& p : patches)
    for (const tsdf::DecodedBlock& b : p.blocks)
      count +=
          static_cast<size_t>(std::count_if(b.block.voxels.begin(), b.block.voxels.end(), near));
  const size_t stride = std::max<size_t>(1, (count + kMaxSamples - 1) / kMaxSamples);
  std::vector<tsdf::SdfSample> samples;
  size_t k = 0;
  for (const tsdf::DecodedPatch& p : patches)
    for (const tsdf::DecodedBlock& b : p.blocks)
      for (int z = 0; z < tsdf::kBlockSide; ++z)
        for (int y = 0; y < tsdf::kBlockSide; ++y)
          for (int x = 0; x < tsdf::kBlockSide; ++x) {
            const tsdf::Voxel& v = b.block.at(x, y, z);
            if (!near(v) || k++ % stride != 0) continue;
            const tsdf::VoxelIndex g = b.index * tsdf::kBlockSide + Eigen::Vector3i(x, y, z);
            samples.push_back({tsdf::voxel_center(g, config.voxel_m), v.distance_m});
          }
  return samples;
}

// How far a change of correction moves the samples: at their centroid, plus the turn over
// their spread.
double movement_m(const Eigen::Isometry3d& change, const std::vector<tsdf::SdfSample>& samples,
                  const Eigen::Isometry3d& before) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const tsdf::SdfSample& s : samples) centroid += before * s.position;
  centroid /= static_cast<double>(std::max<size_t>(samples.size(), 1));
  double spread = 0;
  for (const tsdf::SdfSample& s : samples) spread += (before * s.position - centroid).squaredNorm();
  spread = std::sqrt(spread / static_cast<double>(std::max<size_t>(samples.size(), 1)));
  const Eigen::Matrix3d& r = change.linear();
  return (change * centroid - centroid).norm() + spread * std::abs(std::atan2(r(1, 0), r(0, 0)));
}

}  // namespace

std::optional<Eigen::Isometry3d> TsdfMapper::teammate_correction(uint32_t robot) const {
  const auto a = alignment_.find(robot);
  if (a == alignment_.end() || !a->second.applied) return std::nullopt;
  return a->second.T_own_teammate;
}

void TsdfMapper::fuse_teammate(tsdf::DecodedPatch&& patch) {
  // this robot's own (its old process's, after a restart): no correction
  if (patch.robot_id == robot_id()) {
    tsdf::fuse_blocks(global_, patch);
    if (config_.align_teammates) tsdf::fuse_blocks(own_, patch);
    return;
  }
  if (!config_.align_teammates) {
    tsdf::fuse_blocks(global_, patch);
    return;
  }
  const uint32_t author = patch.robot_id;
  Alignment& a = alignment_[author];
  if (a.applied)
    tsdf::fuse_blocks(global_,
                      tsdf::transform_patch(patch, config_.tsdf.voxel_m, a.T_own_teammate));
  else
    tsdf::fuse_blocks(global_, patch);
  a.recent.push_back(std::move(patch));
  if (a.recent.size() > kRecentPatches) a.recent.pop_front();
  if (++a.since_registration < kRegisterEvery) return;
  a.since_registration = 0;
  align(author, a);
}

void TsdfMapper::align(uint32_t author, Alignment& a) {
  const std::vector<tsdf::SdfSample> samples = samples_of(a.recent, config_.tsdf);
  ++stats_.registrations;
  const auto r = tsdf::register_to_map(*own_.snapshot(), samples, a.T_own_teammate);
  if (!r) {  // no overlap yet, or a view that does not constrain it: the next patches may
    ++stats_.registrations_refused;
    SCANCREW_LOG_DEBUG("%s: robot %u's frame: %s", qualified_name().c_str(), author,
                       r.error().c_str());
    return;
  }
  const Eigen::Isometry3d change = r->T_reference_source * a.T_own_teammate.inverse();
  const double moved = movement_m(change, samples, a.T_own_teammate);
  // under a quarter voxel the map would not show the change
  if (moved <= 0.25 * config_.tsdf.voxel_m) return;
  // adopted when the overlap then agrees (residual under a quarter of μ: the surfaces lie
  // within a voxel or so) and clearly better than with the current correction (depth noise
  // and views from other sides leave a residual that small shifts only trade around)
  if (r->rms_after_m > kAgreement * config_.tsdf.truncation_m ||
      r->rms_after_m > kMinImprovement * r->rms_before_m) {
    ++stats_.registrations_refused;
    SCANCREW_LOG_DEBUG("%s: robot %u's frame: residual %.3f -> %.3f m, not adopted",
                       qualified_name().c_str(), author, r->rms_before_m, r->rms_after_m);
    return;
  }
  a.T_own_teammate = r->T_reference_source;
  a.applied = true;
  ++stats_.corrections_adopted;
  if (stats_.corrections_adopted == 1)
    SCANCREW_LOG_INFO(
        "%s: robot %u's frame corrected by %.3f m (rms %.3f -> %.3f m over %zu "
        "voxels); further corrections are counted",
        qualified_name().c_str(), author, moved, r->rms_before_m, r->rms_after_m, r->overlap);
  rebuild_global();
}

// The global estimate from the patches held, each teammate's through its correction. Its
// blocks are emptied rather than removed, so that readers of the snapshots (changed_since)
// see every block that changed, those a correction moved a surface out of too.
void TsdfMapper::rebuild_global() {
  const uint64_t sequence = global_.begin_update();
  std::vector<tsdf::BlockIndex> indices;
  indices.reserve(global_.block_count());
  for (const auto& [index, block] : global_.blocks()) indices.push_back(index);
  for (const tsdf::BlockIndex& index : indices) {
    tsdf::Block& b = global_.touch(index);
    b = tsdf::Block{};
    b.modified = sequence;
  }
  for (const auto& [id, held] : held_) {
    auto decoded = tsdf::decode_patch(held.patch, config_.tsdf);
    if (!decoded) continue;  // checked when it came: cannot fail now
    const auto a = alignment_.find(decoded->robot_id);
    if (decoded->robot_id != robot_id() && a != alignment_.end() && a->second.applied)
      tsdf::fuse_blocks(
          global_, tsdf::transform_patch(*decoded, config_.tsdf.voxel_m, a->second.T_own_teammate));
    else
      tsdf::fuse_blocks(global_, *decoded);
  }
}

}  // namespace scancrew::tsdf_mapper
