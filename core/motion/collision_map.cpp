#include "core/motion/collision_map.hpp"

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <octomap/OcTree.h>

#include <chrono>
#include <cmath>
#include <limits>

namespace scancrew::motion {

namespace {

constexpr int kKeyOffset = 1 << 15;  // OctoMap's tree_max_val at depth 16

// The OctoMap key of a voxel, if the voxel is inside the key range.
bool key_of(const tsdf::VoxelIndex& v, octomap::OcTreeKey& key) {
  for (int i = 0; i < 3; ++i) {
    const int k = v[i] + kKeyOffset;
    if (k < 0 || k > std::numeric_limits<uint16_t>::max()) return false;
    key[static_cast<unsigned>(i)] = static_cast<uint16_t>(k);
  }
  return true;
}

std::shared_ptr<fcl::CollisionGeometryd> body_geometry(const robot::BodyModel& body) {
  const Eigen::Vector3d& r = body.safety_radii_m;
  if (r.x() == r.y() && r.y() == r.z()) return std::make_shared<fcl::Sphered>(r.x());
  return std::make_shared<fcl::Ellipsoidd>(r.x(), r.y(), r.z());
}

}  // namespace

struct CollisionMap::Impl {
  robot::BodyModel body;
  bool unknown_is_occupied = true;
  std::shared_ptr<const tsdf::MapSnapshot> snapshot;
  double voxel_m = 0;
  std::shared_ptr<octomap::OcTree> tree;
  std::unique_ptr<fcl::CollisionObjectd> tree_object;
  std::unique_ptr<fcl::CollisionObjectd> body_object;
  std::unique_ptr<fcl::CollisionObjectd> block_object;  // a never-observed block's box
  Eigen::AlignedBox3i block_extents;                    // observed blocks (inclusive)
  float occupied_log_odds = 0, free_log_odds = 0;
  mutable fcl::CollisionRequestd request;
  mutable size_t checks = 0;

  Impl(const robot::BodyModel& b, bool unknown_occupied)
      : body(b), unknown_is_occupied(unknown_occupied) {
    body_object = std::make_unique<fcl::CollisionObjectd>(body_geometry(body));
    request.num_max_contacts = 1;
    request.enable_contact = false;
  }

  void rebuild(double voxel) {
    voxel_m = voxel;
    tree = std::make_shared<octomap::OcTree>(voxel);
    occupied_log_odds = tree->getClampingThresMaxLog();
    free_log_odds = tree->getClampingThresMinLog();
    // the FCL wrapper reads the tree's root on every query: updates in place are seen
    tree_object = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::OcTreed>(tree));
    const double side = voxel * tsdf::kBlockSide;
    block_object =
        std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::Boxd>(side, side, side));
  }

  // Rewrites a block's voxels (null: the block is gone, its voxels are removed).
  size_t write_block(const tsdf::BlockIndex& index, const tsdf::Block* block, float w_th) {
    size_t out_of_range = 0;
    octomap::OcTreeKey key;
    for (int z = 0; z < tsdf::kBlockSide; ++z)
      for (int y = 0; y < tsdf::kBlockSide; ++y)
        for (int x = 0; x < tsdf::kBlockSide; ++x) {
          const tsdf::VoxelIndex v = index * tsdf::kBlockSide + Eigen::Vector3i(x, y, z);
          if (!key_of(v, key)) {
            ++out_of_range;
            continue;
          }
          bool obstacle = false;
          if (block != nullptr) {
            const tsdf::VoxelState s = tsdf::state_of(block->at(x, y, z), w_th);
            obstacle = s == tsdf::VoxelState::kOccupied ||
                       (unknown_is_occupied && s == tsdf::VoxelState::kUnknown);
          }
          // a voxel no longer an obstacle is set free, not deleted: OctoMap 1.9's
          // deleteNode() trips its own assertion when a deletion empties an inner node;
          // free leaves are pruned together and FCL skips them (log-odds <= 0)
          if (obstacle) {
            tree->setNodeValue(key, occupied_log_odds, /*lazy_eval=*/true);
          } else if (const octomap::OcTreeNode* n = tree->search(key);
                     n != nullptr && n->getLogOdds() > 0) {
            tree->setNodeValue(key, free_log_odds, /*lazy_eval=*/true);
          }
        }
    return out_of_range;
  }

  bool collide_with(const fcl::CollisionObjectd& other) const {
    fcl::CollisionResultd result;
    fcl::collide(body_object.get(), &other, request, result);
    return result.isCollision();
  }
};

CollisionMap::CollisionMap(const robot::BodyModel& body, bool unknown_is_occupied)
    : impl_(std::make_unique<Impl>(body, unknown_is_occupied)) {}
CollisionMap::~CollisionMap() = default;
CollisionMap::CollisionMap(CollisionMap&&) noexcept = default;
CollisionMap& CollisionMap::operator=(CollisionMap&&) noexcept = default;

CollisionMapUpdate CollisionMap::update(std::shared_ptr<const tsdf::MapSnapshot> snapshot) {
  const auto t0 = std::chrono::steady_clock::now();
  Impl& m = *impl_;
  CollisionMapUpdate out;
  const auto w_th = static_cast<float>(snapshot->config().w_th);
  const bool rebuild = !m.snapshot || m.voxel_m != snapshot->voxel_m() ||
                       m.snapshot->config().w_th != snapshot->config().w_th;
  if (rebuild) {
    m.rebuild(snapshot->voxel_m());
    out.rebuilt = true;
    for (const auto& [index, block] : snapshot->blocks()) {
      out.out_of_range += m.write_block(index, block.get(), w_th);
      out.changed.push_back(index);
    }
  } else {
    const auto& before = m.snapshot->blocks();
    for (const auto& [index, block] : snapshot->blocks()) {
      const auto it = before.find(index);
      if (it != before.end() && it->second == block) continue;  // shared: unchanged
      out.out_of_range += m.write_block(index, block.get(), w_th);
      out.changed.push_back(index);
    }
    for (const auto& [index, block] : before)
      if (snapshot->blocks().count(index) == 0) {
        out.out_of_range += m.write_block(index, nullptr, w_th);
        out.changed.push_back(index);
        ++out.removed_blocks;
      }
  }
  if (!out.changed.empty()) {
    m.tree->updateInnerOccupancy();
    m.tree->prune();
  }
  m.block_extents.setEmpty();
  for (const auto& [index, block] : snapshot->blocks()) m.block_extents.extend(index);
  m.snapshot = std::move(snapshot);
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

bool CollisionMap::collides(const Eigen::Isometry3d& T_world_body) const {
  const Impl& m = *impl_;
  ++m.checks;
  if (!m.snapshot) return false;
  m.body_object->setTransform(T_world_body);
  m.body_object->computeAABB();
  if (m.tree->size() > 0 && m.collide_with(*m.tree_object)) return true;
  if (!m.unknown_is_occupied) return false;
  // never-observed blocks under the body's box: unknown space
  const Eigen::Vector3d h = m.body.aabb_half_extents(T_world_body.linear());
  const double block_m = m.voxel_m * tsdf::kBlockSide;
  const Eigen::Vector3d c = T_world_body.translation();
  const Eigen::Vector3i lo = ((c - h) / block_m).array().floor().cast<int>();
  const Eigen::Vector3i hi = ((c + h) / block_m).array().floor().cast<int>();
  const auto& blocks = m.snapshot->blocks();
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x) {
        const tsdf::BlockIndex b(x, y, z);
        if (blocks.count(b) != 0) continue;
        Eigen::Isometry3d T_world_block = Eigen::Isometry3d::Identity();
        T_world_block.translation() = (b.cast<double>() + Eigen::Vector3d::Constant(0.5)) * block_m;
        m.block_object->setTransform(T_world_block);
        m.block_object->computeAABB();
        if (m.collide_with(*m.block_object)) return true;
      }
  return false;
}

bool CollisionMap::has_map() const {
  return impl_->snapshot != nullptr;
}
const std::shared_ptr<const tsdf::MapSnapshot>& CollisionMap::snapshot() const {
  return impl_->snapshot;
}

Eigen::AlignedBox3d CollisionMap::extents() const {
  const Impl& m = *impl_;
  Eigen::AlignedBox3d box;
  if (!m.snapshot || m.block_extents.isEmpty()) return box;
  const double block_m = m.voxel_m * tsdf::kBlockSide;
  box.extend(m.block_extents.min().cast<double>() * block_m);
  box.extend((m.block_extents.max() + Eigen::Vector3i::Ones()).cast<double>() * block_m);
  return box;
}

tsdf::VoxelState CollisionMap::state_at(const Eigen::Vector3d& p) const {
  if (!impl_->snapshot) return tsdf::VoxelState::kUnknown;
  return impl_->snapshot->state_at(p);
}

const robot::BodyModel& CollisionMap::body() const {
  return impl_->body;
}
bool CollisionMap::unknown_is_occupied() const {
  return impl_->unknown_is_occupied;
}
size_t CollisionMap::leaf_count() const {
  return impl_->tree ? impl_->tree->getNumLeafNodes() : 0;
}
size_t CollisionMap::checks() const {
  return impl_->checks;
}

}  // namespace scancrew::motion
