#pragma once

// TsdfMapper: the mapping component (thesis 2.4.1, 3.4.1, 4.4.1). Integrates depth images
// (with the camera pose they carry) into a TSDF and publishes immutable map snapshots.
//
// Modes (param `mode`):
//   single       one robot's depth into one map (chapter 2)
//   centralized  a ground station's mapper: the depth of every robot of the launch file
//                ("/<ns>/depth"), integrated as it arrives into one map (3.4.1)
//   distributed  a robot's manifold map (4.4.1): depth goes into the current patch; after
//                patch_frames depth images (or patch_distance_m travelled) the patch is
//                complete: it is encoded (patch_codec), kept in the private map, published
//                on `patch`, and fused into the global estimate; the robot publishes the
//                IDs it holds on `patch_list`. Teammates' patches ("/<ns>/patch") form the
//                public map. An ID seen in a teammate's list but never received is asked
//                for on `patch_request` after request_delay_s (again every
//                request_retry_s); of the robots that hold it, the nearest to the asker
//                replies on `patch_reply` (those its pool cannot hold now, on the next
//                timer ticks). A patch's index is its last image's stamp in ms, so a
//                restarted robot numbers on after its old process; it asks for that
//                process's patches like a teammate's. The current patch is never shared.
//                A teammate whose "/<ns>/robot_state" reports kLost (the dds_bridge's word
//                for a dead process) is no holder: the nearest live one replies, so a lost
//                robot's patches stay recoverable from the others; any later state brings
//                it back.
//   The global estimate (what the snapshots show) = private + public patches fused
//   (weights summed, distances weight-averaged: patch_codec's fusion), plus the current
//   patch. Own patches are fused as decoded from their wire form, like the teammates'
//   copies, so robots holding the same patches hold the same map.
//   Drift between robots (align_teammates, off by default: see docs/mapping.md, "Drift
//   between robots", for why): each robot's patches are in its own odometry's frame, which
//   drifts. Every few patches of a teammate, its latest patches are registered onto this
//   robot's own patches (core/tsdf/sdf_registration.hpp: x, y, z, yaw); a correction that
//   moves them by more than a quarter voxel and less than the truncation distance (the
//   registration's reach), and cuts the residual to under 0.7 of the current one, is
//   adopted: the teammate's patches are fused through it from then on
//   (core/tsdf/patch_transform.hpp) and the global estimate is rebuilt from the patches
//   held. What is relayed stays as received.
//
// Ports: in `depth` (msg::DepthImage; single and distributed), out `map` (MapUpdate),
// `patch`, `patch_reply` (msg::TsdfPatch), `patch_list` (msg::PatchList),
// `patch_request` (msg::PatchRequest). Teammates' topics by absolute name.
//
// Outputs: mesh_path (binary PLY, coloured by the robot whose patches made each part)
// and octomap_path (.bt) are written when the component stops.
//
// Bad input: depth images with inf or negative values, a size mismatch, bad intrinsics or
// a pose that is not a rigid transform are skipped, counted per reason, logged once; a
// corrupt, truncated or foreign-voxel-size patch is refused the same way. The map is
// unchanged by anything refused.

#include <array>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/enum_names.hpp"
#include "core/tsdf/integrator.hpp"
#include "core/tsdf/patch_codec.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/map_update.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::tsdf_mapper {

// the core this component puts in the graph (core/tsdf)
using tsdf::Integrator;
using tsdf::MapSnapshot;
using tsdf::TsdfConfig;
using tsdf::TsdfMap;

// Which depth goes into which map (param `mode`; see above).
enum class MapMode : uint8_t { kSingle, kCentralized, kDistributed };

inline constexpr EnumNames<MapMode, 3> kMapModeNames = {{{MapMode::kSingle, "single"},
                                                         {MapMode::kCentralized, "centralized"},
                                                         {MapMode::kDistributed, "distributed"}}};

// How the mesh written to mesh_path is coloured (param `mesh_colour`).
enum class MeshColour : uint8_t { kOwner, kNone };

inline constexpr EnumNames<MeshColour, 2> kMeshColourNames = {
    {{MeshColour::kOwner, "owner"}, {MeshColour::kNone, "none"}}};

struct TsdfMapperStats {
  uint64_t frames = 0, integrated = 0;
  uint64_t rejected_frames = 0;  // bad depth images (check_frame)
  uint64_t patches_made = 0, patches_received = 0, patches_rejected = 0, duplicates = 0;
  // patch completions held back: nothing new for the team yet (adds_information); the frames
  // stay in the current patch, which goes out once it adds something
  uint64_t patches_held_back = 0;
  uint64_t requests_sent = 0, replies_sent = 0;
  uint64_t patch_wire_bytes = 0;  // completed patches as sent (sum)
  uint64_t patch_raw_bytes = 0;   // the same patches as raw float blocks (sum)
  uint64_t snapshots = 0;
  double integrate_ms_sum = 0;
  double integrate_ms_max = 0;
  // drift between robots (align_teammates)
  uint64_t registrations = 0, registrations_refused = 0, corrections_adopted = 0;
};

class TsdfMapper final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "TSDF mapping: depth -> map snapshots; patches shared between robots (distributed)";
  struct Config {
    TsdfConfig tsdf;
    MapMode mode = MapMode::kSingle;  // single | centralized | distributed
    uint32_t patch_frames = 5;        // depth images per patch (thesis 4.6: 5)
    double patch_distance_m = 0;      // or this much travel (0: off)
    uint32_t snapshot_every = 1;      // publish a snapshot every N integrated images
    bool publish_map = true;          // false: no map topic (a map only its mesh is kept of)
    double request_delay_s = 1.0;     // a listed patch missing this long is requested
    double request_retry_s = 2.0;     // and requested again this often
    int compression_level = 3;        // zstd level of the patch payload
    uint32_t depth_queue_depth = 4;
    // the depth topic, relative: the robot's (single, distributed; a remap works too) or each
    // robot's "/<ns>/<depth_topic>" (centralized, which has no per-robot remap); e.g.
    // depth_masked, the depth_mask's output
    std::string depth_topic = "depth";
    // written when the component stops (empty: not written)
    std::string mesh_path;                        // the global estimate's mesh, binary PLY
    MeshColour mesh_colour = MeshColour::kOwner;  // owner (robots' patches in their colour) | none
    double mesh_min_weight = 0;    // MesherConfig::min_weight: 0 meshes every observed voxel
    std::string octomap_path;      // known space as an OctoMap (.bt)
    bool align_teammates = false;  // distributed: register teammates' patches (see above)
  };
  static Config read_config(ParamReader& p);

  TsdfMapper(ComponentContext context, Config config);
  ~TsdfMapper() override;

  const TsdfMapperStats& stats() const { return stats_; }
  const Config& config() const { return config_; }
  void summarize(RunSummary& into) const override;
  // The current global estimate (a fresh snapshot; for tests, tools and the end of a run).
  std::shared_ptr<const MapSnapshot> snapshot() const;
  // IDs of the patches held (private + public).
  std::vector<uint64_t> held_patches() const;
  // The correction adopted for a teammate's frame (align_teammates); nullopt: none.
  std::optional<Eigen::Isometry3d> teammate_correction(uint32_t robot) const;

 private:
  struct Held {
    msg::TsdfPatch patch;  // encoded, as received or sent: replies reuse it
    bool own = false;
  };
  // A teammate's frame as this robot's map sees it (align_teammates), by the patches' author.
  struct Alignment {
    Eigen::Isometry3d T_own_teammate = Eigen::Isometry3d::Identity();
    bool applied = false;                   // a correction was adopted
    std::deque<tsdf::DecodedPatch> recent;  // its latest patches, registered together
    uint32_t since_registration = 0;
  };
  struct Teammate {
    uint32_t id = 0;
    std::string ns;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    bool has_position = false;
    std::vector<uint64_t> holds;  // from its last patch list, sorted
    bool lost = false;            // its latest robot_state is kLost
  };

  Result<void, std::string> on_configure() override;
  void on_deactivate() override;
  void write_outputs();
  void on_depth(const msg::DepthImage& depth);
  void complete_patch();
  bool adds_information() const;
  void on_patch(const msg::TsdfPatch& patch);
  // tsdf_mapper_alignment.cpp: a teammate's decoded patch into the global estimate, through
  // its correction; the registration; the estimate rebuilt after a new correction
  void fuse_teammate(tsdf::DecodedPatch&& patch);
  void align(uint32_t author, Alignment& alignment);
  void rebuild_global();
  void on_patch_list(uint32_t from, const msg::PatchList& list);
  void on_request(const msg::PatchRequest& request);
  void on_teammate_state(size_t teammate, const msg::RobotState& state);
  void check_missing();
  void send_replies();
  void publish_list();
  void publish_snapshot(int64_t stamp_ns);
  Eigen::Vector3d position_of(uint32_t robot) const;

  Config config_;
  Integrator integrator_;
  TsdfMap global_;               // private + public patches (distributed) or the whole map
  TsdfMap current_;              // the patch being built (distributed)
  uint32_t current_frames_ = 0;  // images since the current patch was last checked
  bool current_open_ = false;    // the current patch has its anchor (its first image)
  bool made_any_ = false;        // a patch made yet
  uint32_t last_index_ = 0;      // the last patch's index
  Eigen::Isometry3d current_anchor_ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
  double current_travel_m_ = 0;
  bool have_last_position_ = false;
  std::map<uint64_t, Held> held_;
  TsdfMap own_;  // own patches only: what teammates' patches are registered to
  std::map<uint32_t, Alignment> alignment_;               // by the patches' author
  std::map<std::pair<uint32_t, uint64_t>, size_t> asks_;  // (asker, patch): times asked
  std::set<uint64_t> replies_due_;  // patches asked of this robot, not sent yet (the pool)
  std::map<uint64_t, int64_t> missing_since_ns_, last_request_ns_;
  std::vector<Teammate> teammates_;
  Eigen::Vector3d own_position_ = Eigen::Vector3d::Zero();
  std::array<bool, 4> logged_{};
  uint32_t frames_since_snapshot_ = 0;
  int64_t last_stamp_ns_ = 0;

  Publisher<msg::MapUpdate> map_;
  Publisher<msg::TsdfPatch> patch_, reply_;
  Publisher<msg::PatchList> list_;
  Publisher<msg::PatchRequest> request_;
  TsdfMapperStats stats_;
  std::vector<uint32_t> robots_integrated_;  // MapUpdate::robots_integrated
};

}  // namespace scancrew::tsdf_mapper
