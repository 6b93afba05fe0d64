// TsdfMapper's distributed mode (docs/mapping.md, "Patches"): patches made when they add
// information, fused from teammates, listed, requested when missing and relayed on request.

#include <algorithm>
#include <cmath>
#include <limits>

#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "core/tsdf/patch_codec.hpp"
#include "core/tsdf/patch_fusion.hpp"
#include "executors/log.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::tsdf_mapper {

using tsdf::Block;
using tsdf::fuse_voxel;
using tsdf::kBlockVoxels;
using tsdf::make_patch_id;
using tsdf::Voxel;
using tsdf::VoxelState;

// Whether the current patch tells the team something its estimate lacks. For some voxel it
// observes, fusing it into the global estimate (every patch of the team that this robot
// holds) would
//   - change its state (thesis eq. 1.1): unknown -> known, or occupied <-> empty with the
//     fused distance more than half a voxel from the surface (a surface that moved by more
//     than the map can show; depth noise at a resting surface flips states back and forth
//     within it), or
//   - at least double the evidence of a known voxel (the patch's weight >= the estimate's):
//     a closer or new look, which sharpens the distance.
// A robot at rest, or retracing mapped space, makes patches that do neither: they are held
// back, their images staying in the current patch (and in this robot's snapshots), which is
// checked again after the next patch_frames images and goes out once it adds something —
// a scene that changed, a faint view that became known, enough new looks to double the
// estimate's evidence. So no evidence is lost, and at rest patches go out at doubling
// intervals until the view saturates, then stop; held, every robot would keep each for the
// rest of the mission (docs/mapping.md, "Patches").
bool TsdfMapper::adds_information() const {
  const auto w_max = static_cast<float>(config_.tsdf.max_weight);
  const auto w_th = static_cast<float>(config_.tsdf.w_th);
  const auto half_voxel = static_cast<float>(config_.tsdf.voxel_m / 2);
  const Block empty{};
  for (const auto& [index, block] : current_.blocks()) {
    const Block* g = global_.find(index);
    if (g == nullptr) g = &empty;
    for (size_t i = 0; i < size_t{kBlockVoxels}; ++i) {
      const Voxel& s = block->voxels[i];
      if (!(s.weight > 0)) continue;
      const Voxel& d = g->voxels[i];
      const VoxelState before = state_of(d, w_th);
      if (before != VoxelState::kUnknown && s.weight >= d.weight && d.weight < w_max) return true;
      Voxel fused = d;
      fuse_voxel(fused, s, w_max);
      const VoxelState after = state_of(fused, w_th);
      if (after == before) continue;
      if (before == VoxelState::kUnknown || std::abs(fused.distance_m) > half_voxel) return true;
    }
  }
  return false;
}

void TsdfMapper::complete_patch() {
  if (!adds_information()) {
    ++stats_.patches_held_back;
    current_frames_ = 0;
    current_travel_m_ = 0;
    return;
  }
  // the index: the stamp of the patch's last frame in ms (modulo 2^32), kept increasing. A
  // robot whose process restarted numbers on from where its clock is, after every index its
  // old process used: the team never takes a new patch for an old one (docs/mapping.md)
  auto index = static_cast<uint32_t>(last_stamp_ns_ / 1'000'000);
  if (made_any_ && static_cast<int32_t>(index - last_index_) <= 0) index = last_index_ + 1;
  made_any_ = true;
  last_index_ = index;
  Held held;
  held.own = true;
  msg::TsdfPatch& p = held.patch;
  p.patch_id = make_patch_id(robot_id(), index);
  p.robot_id = robot_id();
  p.index = index;
  p.T_world_patch = msg::to_msg(current_anchor_);
  auto encoded = encode_patch(current_.blocks(), config_.tsdf, p, config_.compression_level);
  if (!encoded) {
    SCANCREW_LOG_ERROR("%s: patch %u not encoded: %s", qualified_name().c_str(), index,
                       encoded.error().c_str());
  } else {
    stats_.patch_wire_bytes += encoded->wire_bytes;
    stats_.patch_raw_bytes += encoded->raw_float_bytes;
    ++stats_.patches_made;
    p.header.stamp_ns = last_stamp_ns_;
    // fused as the teammates will fuse it (quantised): every robot holding the same
    // patches has the same global estimate, bit for bit
    global_.advance_sequence_to(current_.sequence());
    if (auto own = decode_patch(p, config_.tsdf)) {
      fuse_blocks(global_, *own);
      if (config_.align_teammates) fuse_blocks(own_, *own);
    } else {
      SCANCREW_LOG_ERROR("%s: own patch %u does not decode (%s): fused unquantised",
                         qualified_name().c_str(), index, own.error().c_str());
      fuse_map(global_, current_.blocks(), robot_id());
    }
    if (auto loan = patch_.loan()) {
      **loan = p;
      (void)patch_.publish(std::move(*loan));
    }
    held_.emplace(p.patch_id, std::move(held));
    publish_list();
  }
  current_.clear();
  current_frames_ = 0;
  current_open_ = false;
}

void TsdfMapper::on_patch(const msg::TsdfPatch& patch) {
  // a patch of this robot's id that it does not hold is its old process's (it restarted):
  // taken like a teammate's
  if (held_.contains(patch.patch_id)) {
    ++stats_.duplicates;
    return;
  }
  auto decoded = decode_patch(patch, config_.tsdf);
  if (!decoded) {
    ++stats_.patches_rejected;
    if (!logged_[1]) {
      logged_[1] = true;
      SCANCREW_LOG_WARN("%s: patch %u.%u from robot %u refused: %s (further ones are counted)",
                        qualified_name().c_str(), patch.robot_id, patch.index,
                        patch.header.robot_id, decoded.error().c_str());
    }
    return;
  }
  global_.advance_sequence_to(current_.sequence());
  held_.emplace(patch.patch_id, Held{patch, false});
  fuse_teammate(std::move(*decoded));
  ++stats_.patches_received;
  missing_since_ns_.erase(patch.patch_id);
  last_request_ns_.erase(patch.patch_id);
  publish_list();
  publish_snapshot(last_stamp_ns_);
}

void TsdfMapper::on_patch_list(uint32_t from, const msg::PatchList& list) {
  // kept sorted in one block (a list arrives about once a second per teammate and holds
  // every patch of the team: no node per id)
  std::vector<uint64_t>* holds = nullptr;
  for (Teammate& t : teammates_)
    if (t.id == from) holds = &t.holds;
  if (holds != nullptr) {
    holds->assign(list.patch_ids.begin(), list.patch_ids.end());
    if (!std::is_sorted(holds->begin(), holds->end())) std::sort(holds->begin(), holds->end());
    // what the lister holds was answered: its asks are forgotten
    std::erase_if(asks_, [&](const auto& kv) {
      return kv.first.first == from &&
             std::binary_search(holds->begin(), holds->end(), kv.first.second);
    });
  }
  const int64_t now = clock().now_ns();
  // this robot's own ids among them too: its old process's patches, after a restart
  for (uint64_t id : list.patch_ids)
    if (!held_.contains(id)) missing_since_ns_.try_emplace(id, now);
}

void TsdfMapper::check_missing() {
  if (missing_since_ns_.empty()) return;
  const int64_t now = clock().now_ns();
  const auto delay = static_cast<int64_t>(config_.request_delay_s * 1e9);
  const auto retry = static_cast<int64_t>(config_.request_retry_s * 1e9);
  std::vector<uint64_t> wanted;
  for (const auto& [id, since] : missing_since_ns_) {
    if (now - since < delay) continue;
    const auto last = last_request_ns_.find(id);
    if (last != last_request_ns_.end() && now - last->second < retry) continue;
    wanted.push_back(id);
    last_request_ns_[id] = now;
  }
  if (wanted.empty()) return;
  auto loan = request_.loan();
  if (!loan) return;
  (*loan)->header.stamp_ns = now;
  (*loan)->from_robot = robot_id();
  (*loan)->patch_ids = std::move(wanted);
  stats_.requests_sent += (*loan)->patch_ids.size();
  (void)request_.publish(std::move(*loan));
}

Eigen::Vector3d TsdfMapper::position_of(uint32_t robot) const {
  if (robot == robot_id()) return own_position_;
  for (const Teammate& t : teammates_)
    if (t.id == robot) return t.position;
  return Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
}

void TsdfMapper::on_request(const msg::PatchRequest& request) {
  const Eigen::Vector3d asker = position_of(request.from_robot);
  for (uint64_t id : request.patch_ids) {
    if (!held_.contains(id)) continue;
    // of the robots known to hold it (the asker aside), the nearest to the asker answers
    // (ties to the lower robot id), but for the patch's author while another holds it: its
    // broadcast did not reach the asker, its reply may not either (the asker out of its
    // range: another robot relays, thesis Fig. 4.2). Asked again (the asker's retry: that
    // one's reply did not come), the next nearest; once each was asked, every holder answers
    const auto author = static_cast<uint32_t>(id >> 32);
    std::vector<std::pair<double, uint32_t>> holders{
        {(position_of(robot_id()) - asker).norm(), robot_id()}};
    for (const Teammate& t : teammates_)
      if (t.id != request.from_robot && !t.lost && t.has_position &&
          std::binary_search(t.holds.begin(), t.holds.end(), id))
        holders.emplace_back((t.position - asker).norm(), t.id);
    if (holders.size() > 1)
      std::erase_if(holders, [&](const auto& h) { return h.second == author; });
    std::sort(holders.begin(), holders.end());
    const size_t asked = asks_[{request.from_robot, id}]++;
    if (asked >= holders.size() || holders[asked].second == robot_id()) replies_due_.insert(id);
  }
  send_replies();
}

// The replies due, as far as the reply pool allows; the rest on the next timer tick (a
// robot catching up after a restart or a partition asks for many at once: none is dropped)
void TsdfMapper::send_replies() {
  while (!replies_due_.empty()) {
    const auto it = held_.find(*replies_due_.begin());
    if (it == held_.end()) {
      replies_due_.erase(replies_due_.begin());
      continue;
    }
    auto loan = reply_.loan();
    if (!loan) return;
    **loan = it->second.patch;
    (void)reply_.publish(std::move(*loan));
    ++stats_.replies_sent;
    replies_due_.erase(replies_due_.begin());
  }
}

void TsdfMapper::on_teammate_state(size_t teammate, const msg::RobotState& state) {
  Teammate& t = teammates_[teammate];
  const bool lost = state.mode == msg::RobotState::Mode::kLost;
  if (lost == t.lost) return;
  t.lost = lost;
  SCANCREW_LOG_INFO("%s: robot %u %s", qualified_name().c_str(), t.id,
                    lost ? "lost: no longer counted as a holder of patches"
                         : "back: counted as a holder of patches again");
}

void TsdfMapper::publish_list() {
  auto loan = list_.loan();
  if (!loan) return;
  (*loan)->header.stamp_ns = last_stamp_ns_;
  (*loan)->patch_ids.clear();
  for (const auto& [id, held] : held_) (*loan)->patch_ids.push_back(id);
  (void)list_.publish(std::move(*loan));
}

}  // namespace scancrew::tsdf_mapper
