#pragma once

// MapUpdate: the in-process message that carries an immutable map snapshot from the
// tsdf_mapper to its readers (ISE extraction, planners, mesher). The snapshot itself is
// shared, never copied: readers keep the shared_ptr as long as they need a consistent map.
// Not a wire message: robots exchange patches (msg::TsdfPatch), not snapshots.

#include <cstdint>
#include <memory>
#include <vector>

#include "core/tsdf/tsdf_map.hpp"
#include "interfaces/header.hpp"

namespace scancrew::msg {

struct MapUpdate {
  static constexpr const char* kTypeName = "scancrew/MapUpdate";
  msg::Header header;  // stamp: the capture time of the newest depth image integrated
  std::shared_ptr<const tsdf::MapSnapshot> map;
  uint64_t frames_integrated = 0;  // depth images in the map so far (all sources)
  uint32_t patches = 0;            // completed patches fused (distributed mode)
  // the robots (their depth images' header.robot_id) this mapper integrated a depth image
  // of, ascending: a mission is not complete while a robot has none (mission_monitor)
  std::vector<uint32_t> robots_integrated;
};

}  // namespace scancrew::msg
