#pragma once

// IseExtractor: the perception module's ISE stage (thesis 2.4.2, 2.4.3). On each map
// snapshot from the tsdf_mapper (`map`, MapUpdate) it updates the ISE set, C_rem, the
// merged viewpoints and their clusters incrementally (ise_pipeline.hpp) and publishes
//   ises      msg::IseSet: ISE centres, view directions, C_rem, |C_ins|, completion
//   clusters  msg::ViewpointClusters: clusters with gains, robot types, viewpoints
// Completion (C_ins = ∅ over completion_updates consecutive updates) is logged once.
//
// Parameters: it plans for the kinds of the launch file's robots; per kind,
// `<type>_delta_pose_m`, `<type>_fov_h_deg`, `<type>_fov_v_deg`, `<type>_min_range_m`,
// `<type>_max_range_m`, `<type>_clearance_m` (default: the body's bounding radius,
// robot::BodyModel), and for ground robots `ground_camera_height_m`, `ground_floor_z_m` (the
// body's height is its BodyModel's); then merge_distance_m, merge_angle_deg, d_v_m, d_v_max_m,
// gain_rows, gain_cols, completion_updates; region_min_m, region_max_m (the box to
// reconstruct: ISEs outside it are dropped; default everywhere); ply_path (a picture of the
// last result, written when the component stops: ise_ply.hpp).
// Visited and still incomplete (give_up_visits > 0; a deviation from the thesis, docs/ise.md):
// an ISE that some viewpoint sees while a robot of the team stands at that viewpoint
// (within visit_distance_m, horizontally for a ground viewpoint, and visit_angle_deg of its
// yaw; poses from each robot's `pose` port, its remap in the robot's namespace) give_up_visits
// times, and is still an ISE, is given up: C_rem from then on (a corner whose far side no camera
// can reach stays an ISE for good, and its viewpoint would be visited for ever). A robot's stay at
// a viewpoint counts a visit on arrival and one more per visit_period_s it stays, so that the rule
// gives up after the same looks whatever the map's update rate: a station's map updates once per
// robot's snapshot, and a distributed robot's once more per patch. A viewpoint a robot's low-level
// planner skipped (/<ns>/skipped_goal) counts one visit too: an ISE that only unreachable
// viewpoints see is given up after give_up_visits skips. Out-of-range values fail at configuration;
// the map's W_th and voxel size are checked on the first snapshot.

#include <cstdint>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "core/ise/ise_pipeline.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/map_update.hpp"

namespace scancrew::ise_extractor {

// the core this component puts in the graph (core/ise)
using ise::IseConfig;
using ise::IsePipeline;
using ise::IseResult;
using ise::IseStats;
using tsdf::VoxelIndex;

class IseExtractor final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "ISEs, viewpoints, clusters and gains from the map snapshots (thesis 2.4.2-2.4.3)";
  struct Config {
    IseConfig ise;
    std::string ply_path;    // written when the component stops: ise_ply.hpp (empty: not)
    int give_up_visits = 0;  // 0: never give an ISE up (the thesis)
    double visit_distance_m = 0.3;
    double visit_angle_deg = 20.0;
    // a robot's stay at a viewpoint counts a visit on arrival and one more per this much
    // time it stays (0: every map update). Default: the update period of one robot's own
    // map (snapshot_every 5 frames at 5 Hz)
    double visit_period_s = 1.0;
  };
  static Config read_config(ParamReader& p);

  IseExtractor(ComponentContext context, Config config);

  // The last result (tests, benchmarks); null before the first map.
  const IseResult* last() const { return pipeline_ ? &pipeline_->result() : nullptr; }
  uint64_t updates() const { return updates_; }

 private:
  Result<void, std::string> on_configure() override;
  void on_deactivate() override;
  void on_map(const msg::MapUpdate& update);
  void publish(const IseResult& r, int64_t stamp_ns);
  void count_visits(const IseResult& r, int64_t stamp_ns);
  struct RobotPose;
  // Marks in `looked` the ISEs that the viewpoints at `pose` (within visit_distance_m and
  // max_angle_rad of its yaw) see or were made for.
  void mark_looked(const IseResult& r, const RobotPose& pose, double max_angle_rad,
                   std::vector<uint8_t>& looked) const;

  Config config_;
  std::optional<IsePipeline> pipeline_;
  Publisher<msg::IseSet> ises_;
  Publisher<msg::ViewpointClusters> clusters_;
  uint64_t updates_ = 0;
  double ms_sum_ = 0, ms_max_ = 0;
  IseStats stage_sum_;  // the stages' times summed over the updates (ms)
  bool failed_ = false, completion_logged_ = false;
  struct RobotPose {
    bool seen = false;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double yaw_rad = 0;
  };
  std::vector<RobotPose> team_poses_;
  // viewpoints a robot's low-level planner skipped (/<ns>/skipped_goal: no path, a stall,
  // over its detour budget) since the last update: each counts one visit, as if the robot
  // had stood there, so that an ISE only unreachable viewpoints see is given up too
  std::vector<RobotPose> skipped_;
  std::unordered_map<VoxelIndex, int, tsdf::BlockIndexHash> visits_;
  // per robot: where it has stood since it stopped moving, and when each ISE it looked at
  // from there last counted a visit
  struct Stay {
    bool active = false;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double yaw_rad = 0;
    std::unordered_map<VoxelIndex, int64_t, tsdf::BlockIndexHash> counted;
  };
  std::vector<Stay> stays_;
};

}  // namespace scancrew::ise_extractor
