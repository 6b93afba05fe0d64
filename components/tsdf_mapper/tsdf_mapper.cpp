#include "components/tsdf_mapper/tsdf_mapper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/tsdf/mesher.hpp"
#include "core/tsdf/octomap_export.hpp"
#include "core/tsdf/patch_fusion.hpp"
#include "core/tsdf/ply_mesh.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::tsdf_mapper {

using tsdf::Block;
using tsdf::BlockTable;
using tsdf::DepthFrame;
using tsdf::Mesh;
using tsdf::Mesher;
using tsdf::MesherConfig;
using tsdf::PlyColour;
using tsdf::Weld;
using tsdf::write_ply;

namespace {

bool unit_quaternion(const msg::Quat& q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return std::isfinite(n) && std::abs(n - 1.0) < 1e-6;
}

}  // namespace

TsdfMapper::Config TsdfMapper::read_config(ParamReader& p) {
  Config c;
  p.optional("voxel_m", c.tsdf.voxel_m, {0.005, 10}).doc("voxel edge r_v (m)");
  c.tsdf.truncation_m = 3 * c.tsdf.voxel_m;
  p.optional("truncation_m", c.tsdf.truncation_m, {0.005, 1000})
      .doc("truncation distance μ (m; default 3 voxels)");
  p.optional("w_th", c.tsdf.w_th, {1e-9, 1e9})
      .doc("W_th: a voxel is known when its weight w ≥ W_th");
  p.optional("max_weight", c.tsdf.max_weight, {1e-9, 1e9}).doc("the weight w saturates here");
  p.optional("min_range_m", c.tsdf.min_range_m, {0, 1000})
      .doc("depth nearer than this is not integrated (m)");
  p.optional("max_range_m", c.tsdf.max_range_m, {0.01, 1000})
      .doc("depth farther than this is not integrated (m)");
  p.optional("clear_beyond_range", c.tsdf.clear_beyond_range)
      .doc("+inf pixels (no return) clear their ray up to max_range_m − μ; off: skipped like NaN");
  p.choice("weight", c.tsdf.weight, tsdf::kTsdfWeightNames)
      .doc("integration weight: inverse_square (1/z²) or constant (1)");
  p.optional("tile_px", c.tsdf.tile_px, {1, 64})
      .doc("block selection: depth tiles of tile_px² pixels");
  if (auto problem = c.tsdf.validate(); !problem.empty()) p.report("voxel_m", problem);
  p.choice("mode", c.mode, kMapModeNames)
      .doc(
          "single (one robot, one map), centralized (a station maps every robot's depth) or "
          "distributed (patches shared between robots)");
  p.optional("patch_frames", c.patch_frames, {1, 100000})
      .doc("distributed: depth images per patch");
  p.optional("patch_distance_m", c.patch_distance_m, {0, 1e6})
      .doc("distributed: a patch is also complete after this much travel (m; 0: off)");
  p.optional("snapshot_every", c.snapshot_every, {1, 100000})
      .doc("publish a map snapshot every N integrated images");
  p.optional("publish_map", c.publish_map)
      .doc("false: no map topic (a map only its mesh is kept of)");
  p.optional("request_delay_s", c.request_delay_s, {0, 3600})
      .doc("distributed: a teammate's listed patch missing this long is requested (s)");
  p.optional("request_retry_s", c.request_retry_s, {0.01, 3600})
      .doc("distributed: and requested again this often (s)");
  p.optional("compression_level", c.compression_level, {1, 19})
      .doc("zstd level of the patch payload");
  p.optional("depth_queue_depth", c.depth_queue_depth, {1, 1000})
      .doc("queue depth of the depth subscription(s)");
  p.optional("depth_topic", c.depth_topic)
      .doc(
          "the depth topic, relative: the robot's, or each robot's /<ns>/<depth_topic> "
          "(centralized); e.g. depth_masked");
  if (c.depth_topic.empty() || c.depth_topic.front() == '/')
    p.report("depth_topic", "'" + c.depth_topic + "' must be a relative topic name (e.g. depth)");
  p.optional("mesh_path", c.mesh_path)
      .doc(
          "the global estimate's mesh (binary PLY), written when the component stops (empty: not "
          "written)");
  p.choice("mesh_colour", c.mesh_colour, kMeshColourNames)
      .doc("mesh colours: owner (each robot's patches in its colour) or none");
  p.optional("mesh_min_weight", c.mesh_min_weight, {0, 1e6})
      .doc("only voxels with at least this weight are meshed (0: every observed voxel)");
  p.optional("octomap_path", c.octomap_path)
      .doc(
          "known space as an OctoMap (.bt), written when the component stops (empty: not written)");
  p.optional("align_teammates", c.align_teammates)
      .doc(
          "distributed: register teammates' patches onto this robot's to correct drift "
          "(docs/mapping.md)");
  return c;
}

TsdfMapper::TsdfMapper(ComponentContext context, Config config)
    : Component(std::move(context)),
      config_(std::move(config)),
      integrator_(config_.tsdf),
      global_(config_.tsdf),
      current_(config_.tsdf),
      own_(config_.tsdf) {}

TsdfMapper::~TsdfMapper() = default;

Result<void, std::string> TsdfMapper::on_configure() {
  if (config_.publish_map) map_ = create_publisher<msg::MapUpdate>("map", {.pool_size = 4});
  const auto on_depth_sample = [this](Sample<msg::DepthImage>&& s) { on_depth(*s); };
  if (config_.mode == MapMode::kCentralized) {
    if (team().empty())
      return make_unexpected(std::string("mode centralized needs the robots: section"));
    for (const TeamMember& m : team())
      create_subscription<msg::DepthImage>("/" + m.ns + "/" + config_.depth_topic,
                                           {.depth = config_.depth_queue_depth}, on_depth_sample);
    return {};
  }
  create_subscription<msg::DepthImage>(config_.depth_topic, {.depth = config_.depth_queue_depth},
                                       on_depth_sample);
  if (config_.mode != MapMode::kDistributed) return {};

  patch_ = create_publisher<msg::TsdfPatch>("patch", {.pool_size = 4});
  reply_ = create_publisher<msg::TsdfPatch>("patch_reply", {.pool_size = 16});
  list_ = create_publisher<msg::PatchList>("patch_list", {.pool_size = 2});
  request_ = create_publisher<msg::PatchRequest>("patch_request", {.pool_size = 2});
  for (const TeamMember& m : team()) {
    if (m.id == robot_id()) continue;
    teammates_.push_back({.id = m.id, .ns = m.ns});
  }
  for (size_t i = 0; i < teammates_.size(); ++i) {
    const std::string ns = "/" + teammates_[i].ns + "/";
    const auto patch_cb = [this](Sample<msg::TsdfPatch>&& s) { on_patch(*s); };
    create_subscription<msg::TsdfPatch>(ns + "patch", {.depth = 16}, patch_cb);
    create_subscription<msg::TsdfPatch>(ns + "patch_reply", {.depth = 16}, patch_cb);
    create_subscription<msg::PatchList>(
        ns + "patch_list", {.depth = 4},
        [this, i](Sample<msg::PatchList>&& s) { on_patch_list(teammates_[i].id, *s); });
    create_subscription<msg::PatchRequest>(
        ns + "patch_request", {.depth = 8},
        [this](Sample<msg::PatchRequest>&& s) { on_request(*s); });
    create_teammate_subscription<msg::Odometry>(
        "pose", teammates_[i].ns, {.depth = 2}, [this, i](Sample<msg::Odometry>&& s) {
          if (s->tracking_quality <= 0) return;
          teammates_[i].position = msg::to_eigen(s->T_world_body.position);
          teammates_[i].has_position = true;
        });
    // the latest state is all that counts (lost or not); depth 1 holds one slot of the
    // low-level planner's small pool at most
    create_subscription<msg::RobotState>(
        ns + "robot_state", {.depth = 1},
        [this, i](Sample<msg::RobotState>&& s) { on_teammate_state(i, *s); });
  }
  const auto period = std::chrono::nanoseconds(
      std::llround(std::min(config_.request_delay_s, config_.request_retry_s) * 0.5e9 + 1e7));
  create_timer(period, [this] {
    check_missing();
    send_replies();
  });
  return {};
}

void TsdfMapper::on_deactivate() {
  const TsdfMapperStats& s = stats_;
  SCANCREW_LOG_INFO("%s: %llu depth images integrated (%.2f ms mean, %.2f max), %llu refused",
                    qualified_name().c_str(), static_cast<unsigned long long>(s.integrated),
                    s.integrated > 0 ? s.integrate_ms_sum / static_cast<double>(s.integrated) : 0.0,
                    s.integrate_ms_max, static_cast<unsigned long long>(s.rejected_frames));
  if (config_.mode == MapMode::kDistributed)
    SCANCREW_LOG_INFO(
        "%s: patches: %llu made (%.1f kB each on the wire, 1/%.1f of raw float blocks), %llu "
        "held back (nothing new yet), %llu received, %llu refused, %llu duplicates ignored, %llu "
        "requested, %llu replies sent",
        qualified_name().c_str(), static_cast<unsigned long long>(s.patches_made),
        s.patches_made > 0
            ? static_cast<double>(s.patch_wire_bytes) / 1e3 / static_cast<double>(s.patches_made)
            : 0.0,
        s.patch_wire_bytes > 0
            ? static_cast<double>(s.patch_raw_bytes) / static_cast<double>(s.patch_wire_bytes)
            : 0.0,
        static_cast<unsigned long long>(s.patches_held_back),
        static_cast<unsigned long long>(s.patches_received),
        static_cast<unsigned long long>(s.patches_rejected),
        static_cast<unsigned long long>(s.duplicates),
        static_cast<unsigned long long>(s.requests_sent),
        static_cast<unsigned long long>(s.replies_sent));
  if (config_.mode == MapMode::kDistributed && config_.align_teammates) {
    std::string corrections;
    for (const auto& [author, a] : alignment_) {
      if (!a.applied) continue;
      const Eigen::Vector3d t = a.T_own_teammate.translation();
      const Eigen::Matrix3d& r = a.T_own_teammate.linear();
      char one[128];
      std::snprintf(one, sizeof one, "; robot %u by (%.3f, %.3f, %.3f) m, %.2f deg", author, t.x(),
                    t.y(), t.z(), std::atan2(r(1, 0), r(0, 0)) * 180.0 / M_PI);
      corrections += one;
    }
    SCANCREW_LOG_INFO(
        "%s: teammates' frames: %llu registrations, %llu refused, %llu corrections "
        "adopted%s",
        qualified_name().c_str(), static_cast<unsigned long long>(s.registrations),
        static_cast<unsigned long long>(s.registrations_refused),
        static_cast<unsigned long long>(s.corrections_adopted), corrections.c_str());
  }
  write_outputs();
}

void TsdfMapper::write_outputs() {
  if (config_.mesh_path.empty() && config_.octomap_path.empty()) return;
  const auto snap = snapshot();
  if (!config_.mesh_path.empty()) {
    Mesher mesher(MesherConfig{.min_weight = config_.mesh_min_weight});
    mesher.full(*snap);
    const Mesh mesh = mesher.assemble(Weld::kAcrossBlocks);
    const auto written = write_ply(
        mesh, config_.mesh_path,
        config_.mesh_colour == MeshColour::kOwner ? PlyColour::kByOwner : PlyColour::kNone);
    if (written)
      SCANCREW_LOG_INFO("%s: wrote %s (%zu triangles)", qualified_name().c_str(),
                        config_.mesh_path.c_str(), mesh.triangles.size());
    else
      report_failure(written.error());
  }
  if (!config_.octomap_path.empty()) {
    const auto written = write_octomap(*snap, config_.octomap_path);
    if (written)
      SCANCREW_LOG_INFO("%s: wrote %s", qualified_name().c_str(), config_.octomap_path.c_str());
    else
      report_failure(written.error());
  }
}

void TsdfMapper::on_depth(const msg::DepthImage& depth) {
  ++stats_.frames;
  DepthFrame frame;
  frame.depth_m = depth.depth_m.data();
  frame.size = depth.depth_m.size();
  frame.width = depth.intrinsics.width;
  frame.height = depth.intrinsics.height;
  frame.fx = depth.intrinsics.fx;
  frame.fy = depth.intrinsics.fy;
  frame.cx = depth.intrinsics.cx;
  frame.cy = depth.intrinsics.cy;
  auto refuse = [&](const std::string& problem) {
    ++stats_.rejected_frames;
    if (!logged_[0]) {
      logged_[0] = true;
      SCANCREW_LOG_WARN("%s: depth image at t = %.3f s skipped: %s (further ones are counted)",
                        qualified_name().c_str(), static_cast<double>(depth.header.stamp_ns) * 1e-9,
                        problem.c_str());
    }
  };
  if (!unit_quaternion(depth.T_world_cam.orientation)) {
    refuse("camera pose quaternion is not unit");
    return;
  }
  frame.T_world_cam = msg::to_eigen(depth.T_world_cam);
  const bool distributed = config_.mode == MapMode::kDistributed;

  // the integrator checks the frame (check_frame) as it reads it, before writing anything
  const auto t0 = std::chrono::steady_clock::now();
  current_.advance_sequence_to(global_.sequence());
  auto integrated = integrator_.integrate(distributed ? current_ : global_, frame);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!integrated) {
    refuse(integrated.error());
    return;
  }
  const Eigen::Vector3d position = frame.T_world_cam.translation();
  own_position_ = position;
  if (distributed && !current_open_) {
    current_anchor_ = frame.T_world_cam;
    current_travel_m_ = 0;
    current_open_ = true;
  } else if (have_last_position_) {
    current_travel_m_ += (position - last_position_).norm();
  }
  last_position_ = position;
  have_last_position_ = true;
  ++stats_.integrated;
  if (!std::binary_search(robots_integrated_.begin(), robots_integrated_.end(),
                          depth.header.robot_id))
    robots_integrated_.insert(std::upper_bound(robots_integrated_.begin(), robots_integrated_.end(),
                                               depth.header.robot_id),
                              depth.header.robot_id);
  stats_.integrate_ms_sum += ms;
  stats_.integrate_ms_max = std::max(stats_.integrate_ms_max, ms);
  last_stamp_ns_ = depth.header.stamp_ns;
  if (distributed) {
    ++current_frames_;
    if (current_frames_ >= config_.patch_frames ||
        (config_.patch_distance_m > 0 && current_travel_m_ >= config_.patch_distance_m))
      complete_patch();
  }
  if (++frames_since_snapshot_ >= config_.snapshot_every) {
    frames_since_snapshot_ = 0;
    publish_snapshot(depth.header.stamp_ns);
  }
}

std::shared_ptr<const MapSnapshot> TsdfMapper::snapshot() const {
  if (current_.block_count() == 0) return global_.snapshot();
  // global ⊕ current: the current patch's blocks fused onto copies of the global ones
  BlockTable<const Block> table;
  table.reserve(global_.block_count() + current_.block_count());
  for (const auto& [index, block] : global_.blocks()) table.emplace(index, block);
  const auto max_weight = static_cast<float>(config_.tsdf.max_weight);
  for (const auto& [index, block] : current_.blocks()) {
    auto merged = std::make_shared<Block>();
    if (const Block* g = global_.find(index)) *merged = *g;
    fuse_block(*merged, *block, max_weight, robot_id());
    merged->modified = std::max(merged->modified, block->modified);
    table[index] = std::move(merged);
  }
  return std::make_shared<const MapSnapshot>(
      config_.tsdf, std::max(global_.sequence(), current_.sequence()), std::move(table));
}

void TsdfMapper::publish_snapshot(int64_t stamp_ns) {
  if (!map_.valid()) return;
  auto loan = map_.loan();
  if (!loan) return;
  (*loan)->header.stamp_ns = stamp_ns;
  (*loan)->map = snapshot();
  (*loan)->frames_integrated = stats_.integrated;
  (*loan)->robots_integrated = robots_integrated_;
  (*loan)->patches = static_cast<uint32_t>(held_.size());
  ++stats_.snapshots;
  (void)map_.publish(std::move(*loan));
}

std::vector<uint64_t> TsdfMapper::held_patches() const {
  std::vector<uint64_t> ids;
  for (const auto& [id, held] : held_) ids.push_back(id);
  return ids;
}

void TsdfMapper::summarize(RunSummary& into) const {
  const std::string& name = qualified_name();
  into.maps.push_back({.component = name.substr(name.rfind('/') + 1),
                       .robot_id = robot_id(),
                       .mode = std::string(name_of(kMapModeNames, config_.mode)),
                       .mesh_path = config_.mesh_path,
                       .octomap_path = config_.octomap_path,
                       .voxel_m = config_.tsdf.voxel_m,
                       .patch_wire_bytes = stats_.patch_wire_bytes});
}

SCANCREW_REGISTER_COMPONENT(TsdfMapper, "tsdf_mapper")

}  // namespace scancrew::tsdf_mapper
