#include "core/tsdf/octomap_export.hpp"

#include <octomap/OcTree.h>

#include <cerrno>
#include <fstream>
#include <system_error>

namespace scancrew::tsdf {

namespace {

constexpr int kKeyOrigin = 1 << 15;  // octomap::OcTree's tree_max_val: the key of x = 0
constexpr int kKeyCount = 1 << 16;

std::string system_error_text() {
  return std::error_code(errno, std::generic_category()).message();  // thread-safe strerror
}

}  // namespace

Result<OctomapStats, std::string> write_octomap(const MapSnapshot& snap, const std::string& path) {
  OctomapStats stats;
  octomap::OcTree tree(snap.voxel_m());
  const auto w_th = static_cast<float>(snap.config().w_th);

  // one update per known voxel (a hit or a miss from the prior makes it occupied or free);
  // inner nodes are brought up to date once at the end
  for (const auto& [index, block] : snap.blocks())
    for (int z = 0; z < kBlockSide; ++z)
      for (int y = 0; y < kBlockSide; ++y)
        for (int x = 0; x < kBlockSide; ++x) {
          const VoxelState state = state_of(block->at(x, y, z), w_th);
          if (state == VoxelState::kUnknown) continue;
          const Eigen::Vector3i key =
              index * kBlockSide + Eigen::Vector3i(x, y, z) + Eigen::Vector3i::Constant(kKeyOrigin);
          if ((key.array() < 0).any() || (key.array() >= kKeyCount).any()) {
            ++stats.out_of_range;
            continue;
          }
          const bool occupied = state == VoxelState::kOccupied;
          tree.updateNode(octomap::OcTreeKey(static_cast<octomap::key_type>(key.x()),
                                             static_cast<octomap::key_type>(key.y()),
                                             static_cast<octomap::key_type>(key.z())),
                          occupied, /*lazy_eval=*/true);
          ++(occupied ? stats.occupied : stats.free);
        }
  tree.updateInnerOccupancy();
  tree.prune();
  stats.leaf_nodes = tree.getNumLeafNodes();

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return make_unexpected("cannot open " + path + ": " + system_error_text());
  // OcTree::writeBinary(), but for its last line: the library's writer prints " done." on
  // stderr (a debug print Debian's build leaves on). The header is its
  // AbstractOccupancyOcTree::writeBinaryConst's, byte for byte.
  tree.toMaxLikelihood();
  tree.prune();
  out << "# Octomap OcTree binary file\n# (feel free to add / change comments, but leave the "
         "first line as it is!)\n#\nid "
      << tree.getTreeType() << "\nsize " << tree.size() << "\nres " << tree.getResolution()
      << "\ndata\n";
  tree.writeBinaryData(out);
  if (!out.good() || !out.flush())
    return make_unexpected("cannot write " + path + ": " + system_error_text());
  stats.bytes = static_cast<size_t>(out.tellp());
  out.close();
  if (out.fail()) return make_unexpected("cannot write " + path + ": " + system_error_text());
  return stats;
}

}  // namespace scancrew::tsdf
