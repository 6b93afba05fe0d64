#include "core/ise/ise_pipeline.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_set>

namespace scancrew::ise {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

using BlockSet = std::unordered_set<BlockIndex, tsdf::BlockIndexHash>;

bool box_meets(const BlockIndex& lo, const BlockIndex& hi, const BlockSet& blocks,
               const BlockIndex& set_lo, const BlockIndex& set_hi) {
  for (int a = 0; a < 3; ++a)
    if (hi[a] < set_lo[a] || lo[a] > set_hi[a]) return false;
  for (const BlockIndex& b : blocks)
    if ((b.array() >= lo.array()).all() && (b.array() <= hi.array()).all()) return true;
  return false;
}

// the blocks within k blocks (per axis) of any of the centres
BlockSet blocks_within(const std::vector<BlockIndex>& centres, int k) {
  BlockSet out;
  for (const BlockIndex& b : centres)
    for (int z = -k; z <= k; ++z)
      for (int y = -k; y <= k; ++y)
        for (int x = -k; x <= k; ++x) out.insert(b + BlockIndex(x, y, z));
  return out;
}

// the smallest box [lo, hi] holding the blocks (lo > hi when there are none)
void block_bounds(const std::vector<BlockIndex>& blocks, BlockIndex& lo, BlockIndex& hi) {
  lo = BlockIndex::Constant(std::numeric_limits<int>::max());
  hi = BlockIndex::Constant(std::numeric_limits<int>::min());
  for (const BlockIndex& b : blocks) {
    lo = lo.cwiseMin(b);
    hi = hi.cwiseMax(b);
  }
}

// the largest clearance region reach over the robot types, metres
double max_clearance_m(const IseConfig& config) {
  double clearance = 0;
  for (const RobotTypeSpec& t : config.robot_types)
    clearance = std::max(
        clearance,
        t.clearance_m + (t.type == RobotKind::kGround ? t.body_height_m + t.camera_height_m : 0.0));
  return clearance;
}

// drops given-up ISEs from each C_q, and the viewpoints left with nothing else to do
void drop_given_up(std::vector<Viewpoint>& viewpoints, const std::vector<uint8_t>& gave_up) {
  // what is left to see from each viewpoint; one that saw only given-up ISEs and was made
  // for given-up ISEs only goes (one made for an ISE still inspectable stays: that ISE's
  // only way to be seen, or given up in turn)
  std::erase_if(viewpoints, [&](Viewpoint& v) {
    const bool saw = !v.seen.empty();
    std::erase_if(v.seen, [&](uint32_t id) { return gave_up[id] != 0; });
    return saw && v.seen.empty() &&
           std::all_of(v.ises.begin(), v.ises.end(), [&](uint32_t id) { return gave_up[id] != 0; });
  });
}

}  // namespace

Result<IsePipeline, std::string> IsePipeline::create(const IseConfig& config, double w_th,
                                                     double voxel_m) {
  if (std::string problem = config.validate(w_th, voxel_m); !problem.empty())
    return make_unexpected(problem);
  return IsePipeline(config);
}

size_t IsePipeline::PoseKeyHash::operator()(const PoseKey& k) const {
  size_t h = static_cast<size_t>(k.type);
  for (int64_t v : {k.x, k.y, k.z, k.yaw}) h = h * 1000003u ^ static_cast<size_t>(v);
  return h;
}

IsePipeline::PoseKey IsePipeline::key_of(const Viewpoint& v) {
  // 0.1 mm and 1 µrad: an unchanged merge gives the same pose to the last bits
  return {static_cast<int>(v.type), std::llround(v.position.x() * 1e4),
          std::llround(v.position.y() * 1e4), std::llround(v.position.z() * 1e4),
          std::llround(v.yaw_rad * 1e6)};
}

const RobotTypeSpec& IsePipeline::spec(RobotKind type) const {
  for (const RobotTypeSpec& t : config_.robot_types)
    if (t.type == type) return t;
  return config_.robot_types.front();  // unreachable: candidates come from these types
}

const IseResult& IsePipeline::full(const tsdf::MapSnapshot& snap) {
  ises_.clear();
  candidates_.clear();
  seen_.clear();
  std::vector<BlockIndex> all;
  all.reserve(snap.block_count());
  for (const auto& [index, block] : snap.blocks()) all.push_back(index);
  states_.rebuild(snap);
  run(snap, all, true);
  return result_;
}

const IseResult& IsePipeline::update(const tsdf::MapSnapshot& snap) {
  if (!have_ || snap.sequence() < sequence_ || snap.voxel_m() != voxel_m_) return full(snap);
  std::vector<BlockIndex> changed = snap.changed_since(sequence_);
  // blocks gone from the map since (a reset region) change their neighbours too, whether
  // or not they held ISEs (their voxels turn unknown next to their neighbours' voxels)
  for (const BlockIndex& index : blocks_)
    if (snap.block(index) == nullptr) changed.push_back(index);
  states_.refresh(snap, changed);
  run(snap, changed, false);
  return result_;
}

void IsePipeline::run(const tsdf::MapSnapshot& snap, const std::vector<BlockIndex>& changed,
                      bool full) {
  const auto t_start = Clock::now();
  IseStats stats;
  stats.full = full;
  stats.changed_blocks = changed.size();
  const double block_m = snap.voxel_m() * tsdf::kBlockSide;

  // 1. ISEs of the dirty blocks: the changed ones and their neighbours that exist
  auto t0 = Clock::now();
  const BlockSet dirty_set = blocks_within(changed, 1);
  std::vector<BlockIndex> dirty(dirty_set.begin(), dirty_set.end());
  std::sort(dirty.begin(), dirty.end(), BlockOrder());
  stats.dirty_blocks = dirty.size();
  BlockIndex dirty_lo, dirty_hi;
  block_bounds(dirty, dirty_lo, dirty_hi);
  extract_dirty(snap, dirty);
  stats.extract_ms = ms_since(t0);

  // 2. candidate viewpoints: new for the dirty blocks; feasibility rechecked where a
  //    changed block is within reach of the clearance region
  t0 = Clock::now();
  const double clearance = max_clearance_m(config_);
  const int k = static_cast<int>(std::ceil((clearance + snap.voxel_m()) / block_m));
  BlockSet near_changed;
  if (!full) near_changed = blocks_within(changed, k);
  make_candidates(dirty);
  check_feasibility(snap, near_changed, full);

  // 3. the ISE list, in block order, and the feasible candidates with global ISE indices
  IseResult out;
  out.map_sequence = snap.sequence();
  IseIndex index;
  std::vector<uint8_t> gave_up;
  std::vector<Viewpoint> feasible_candidates = gather(out, index, gave_up);
  stats.candidates = feasible_candidates.size();

  // 4. merging (2.4.2); each merged pose's robot types
  out.viewpoints = merge(snap, config_, std::move(feasible_candidates));
  assign_types(snap, out.viewpoints);
  stats.viewpoints_ms = ms_since(t0);

  // 5. visibility: cached C_q unless the frustum box meets a dirty block
  t0 = Clock::now();
  if (!full)
    for (auto it = seen_.begin(); it != seen_.end();)
      it = box_meets(it->second.lo, it->second.hi, dirty_set, dirty_lo, dirty_hi) ? seen_.erase(it)
                                                                                  : std::next(it);
  const size_t computed = compute_visibility(snap, block_m, index, out);
  const size_t merged_viewpoints = out.viewpoints.size();
  if (!given_up_.empty()) drop_given_up(out.viewpoints, gave_up);
  for (Viewpoint& v : out.viewpoints) {
    std::sort(v.seen.begin(), v.seen.end());
    for (uint32_t id : v.seen) out.inspectable[id] = 1;
  }
  stats.visibility_computed = computed;
  stats.visibility_reused = merged_viewpoints - computed;
  stats.visibility_ms = ms_since(t0);

  // 6. clusters and gains (2.4.3)
  t0 = Clock::now();
  out.clusters = cluster_viewpoints(out.viewpoints, config_.d_v_m, config_.d_v_max_m);
  compute_gains(out.clusters, out.viewpoints, out.ises.size());
  stats.cluster_ms = ms_since(t0);

  for (uint32_t i = 0; i < out.ises.size(); ++i)
    if (out.inspectable[i] == 0) out.remaining.push_back(i);
  out.inspectable_count = out.ises.size() - out.remaining.size();
  had_ises_ = had_ises_ || !out.ises.empty();
  empty_updates_ = (had_ises_ && out.inspectable_count == 0) ? empty_updates_ + 1 : 0;
  out.complete = empty_updates_ >= config_.completion_updates;
  stats.total_ms = ms_since(t_start);
  out.stats = stats;
  result_ = std::move(out);
  have_ = true;
  sequence_ = snap.sequence();
  blocks_.clear();
  blocks_.reserve(snap.block_count());
  for (const auto& [index, block] : snap.blocks()) blocks_.push_back(index);
  voxel_m_ = snap.voxel_m();
}

// recomputes the ISEs of the dirty blocks (kept only inside the region) into ises_
void IsePipeline::extract_dirty(const tsdf::MapSnapshot& snap,
                                const std::vector<BlockIndex>& dirty) {
  std::vector<std::vector<Ise>> fresh = extract_blocks(snap, dirty);
  for (size_t i = 0; i < dirty.size(); ++i) {
    std::erase_if(fresh[i],
                  [&](const Ise& ise) { return !config_.in_region(ise.center, voxel_m_); });
    if (fresh[i].empty())
      ises_.erase(dirty[i]);
    else
      ises_[dirty[i]] = std::move(fresh[i]);
  }
}

// makes the candidate viewpoints of the dirty blocks' ISEs, all marked to check
void IsePipeline::make_candidates(const std::vector<BlockIndex>& dirty) {
  for (const BlockIndex& b : dirty) {
    const auto it = ises_.find(b);
    if (it == ises_.end()) {
      candidates_.erase(b);
      continue;
    }
    BlockCandidates bc;
    for (uint32_t i = 0; i < it->second.size(); ++i)
      for (const RobotTypeSpec& t : config_.robot_types)
        if (auto c = candidate(it->second[i], t)) {
          c->ises = {i};
          bc.candidates.push_back(std::move(*c));
        }
    bc.feasible.assign(bc.candidates.size(), 2);  // 2: to check
    candidates_[b] = std::move(bc);
  }
}

// checks the feasibility of new candidates and of those near a changed block, in parallel
void IsePipeline::check_feasibility(
    const tsdf::MapSnapshot& snap,
    const std::unordered_set<BlockIndex, tsdf::BlockIndexHash>& near_changed, bool full) {
  // everything to check, in one parallel pass
  std::vector<std::pair<BlockCandidates*, size_t>> to_check;
  for (auto& [b, bc] : candidates_)
    for (size_t i = 0; i < bc.candidates.size(); ++i) {
      if (bc.feasible[i] == 2 || (!full && near_changed.count(tsdf::block_of(tsdf::voxel_of(
                                               bc.candidates[i].position, snap.voxel_m()))) != 0))
        to_check.emplace_back(&bc, i);
    }
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, to_check.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          auto& [bc, j] = to_check[i];
          const Viewpoint& c = bc->candidates[j];
          bc->feasible[j] = feasible(states_, snap.voxel_m(), spec(c.type), c.position) ? 1 : 0;
        }
      });
}

// fills out's ISE list and inspectable flags, index and gave_up; returns the feasible
// candidates (not for given-up ISEs) with global ISE indices
std::vector<Viewpoint> IsePipeline::gather(IseResult& out, IseIndex& index,
                                           std::vector<uint8_t>& gave_up) const {
  std::vector<Viewpoint> feasible_candidates;
  for (const auto& [b, list] : ises_) {
    const auto offset = static_cast<uint32_t>(out.ises.size());
    out.ises.insert(out.ises.end(), list.begin(), list.end());
    const auto it = candidates_.find(b);
    if (it == candidates_.end()) continue;
    for (size_t i = 0; i < it->second.candidates.size(); ++i) {
      if (it->second.feasible[i] != 1) continue;
      Viewpoint c = it->second.candidates[i];
      c.ises[0] += offset;
      feasible_candidates.push_back(std::move(c));
    }
  }
  index.reserve(out.ises.size());
  for (uint32_t i = 0; i < out.ises.size(); ++i) index.emplace(out.ises[i].voxel, i);
  gave_up.assign(out.ises.size(), 0);
  if (!given_up_.empty()) {
    for (uint32_t i = 0; i < out.ises.size(); ++i)
      gave_up[i] = given_up_.contains(out.ises[i].voxel) ? 1 : 0;
    std::erase_if(feasible_candidates, [&](const Viewpoint& c) { return gave_up[c.ises[0]] != 0; });
  }
  out.inspectable.assign(out.ises.size(), 0);
  for (const Viewpoint& c : feasible_candidates) out.inspectable[c.ises[0]] = 1;
  return feasible_candidates;
}

// sets each merged viewpoint's robot types: its own and every other type feasible there
void IsePipeline::assign_types(const tsdf::MapSnapshot& snap,
                               std::vector<Viewpoint>& viewpoints) const {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, viewpoints.size(), 16),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) {
                        Viewpoint& v = viewpoints[i];
                        v.types = robot::kind_bit(v.type);
                        for (const RobotTypeSpec& t : config_.robot_types)
                          if (t.type != v.type && feasible(states_, snap.voxel_m(), t, v.position))
                            v.types |= robot::kind_bit(t.type);
                      }
                    });
}

// fills each viewpoint's C_q, from seen_ where cached, else computed (and cached);
// returns how many were computed
size_t IsePipeline::compute_visibility(const tsdf::MapSnapshot& snap, double block_m,
                                       const IseIndex& index, IseResult& out) {
  std::vector<size_t> compute;
  std::vector<const Seen*> cached(out.viewpoints.size(), nullptr);
  for (size_t i = 0; i < out.viewpoints.size(); ++i) {
    const auto it = seen_.find(key_of(out.viewpoints[i]));
    if (it != seen_.end())
      cached[i] = &it->second;
    else
      compute.push_back(i);
  }
  std::vector<Seen> computed(compute.size());
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, compute.size(), 4), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const Viewpoint& v = out.viewpoints[compute[i]];
          const RobotTypeSpec& t = spec(v.type);
          Seen& s = computed[i];
          view_bounds(t, v.position, v.yaw_rad, block_m, s.lo, s.hi);
          for (uint32_t id : visible_ises(states_, snap.voxel_m(), index, t, config_.gain_rows,
                                          config_.gain_cols, v.position, v.yaw_rad))
            s.ises.push_back(out.ises[id].voxel);
        }
      });
  for (size_t i = 0; i < out.viewpoints.size(); ++i) {
    if (cached[i] == nullptr) continue;
    for (const VoxelIndex& v : cached[i]->ises)
      if (const uint32_t id = index.find(v); id != IseIndex::kNone)
        out.viewpoints[i].seen.push_back(id);
  }
  for (size_t i = 0; i < compute.size(); ++i) {
    Viewpoint& v = out.viewpoints[compute[i]];
    for (const VoxelIndex& voxel : computed[i].ises) v.seen.push_back(index.find(voxel));
    seen_[key_of(v)] = std::move(computed[i]);
  }
  return compute.size();
}

}  // namespace scancrew::ise
