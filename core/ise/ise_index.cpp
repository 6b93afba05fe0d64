#include "core/ise/ise_index.hpp"

namespace scancrew::ise {

void IseIndex::reserve(size_t ises) {
  // ISEs lie on surfaces: a block rarely holds more than a few dozen
  blocks_.reserve(ises / 8 + 1);
  tables_.reserve(ises / 8 + 1);
}

bool IseIndex::emplace(const VoxelIndex& v, uint32_t id) {
  if (id == kNone) return false;
  const auto [it, added] = blocks_.emplace(block_of(v), static_cast<uint32_t>(tables_.size()));
  if (added) tables_.emplace_back().fill(kNone);
  uint32_t& at = tables_[it->second][static_cast<size_t>(slot(v))];
  if (at != kNone) return false;
  at = id;
  ++size_;
  return true;
}

uint32_t IseIndex::find(const VoxelIndex& v) const {
  const BlockIds* ids = block(block_of(v));
  return ids == nullptr ? kNone : (*ids)[static_cast<size_t>(slot(v))];
}

const IseIndex::BlockIds* IseIndex::block(const BlockIndex& b) const {
  const auto it = blocks_.find(b);
  return it == blocks_.end() ? nullptr : &tables_[it->second];
}

}  // namespace scancrew::ise
