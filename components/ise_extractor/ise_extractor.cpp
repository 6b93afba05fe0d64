#include "components/ise_extractor/ise_extractor.hpp"

#include <algorithm>
#include <cmath>

#include "core/ise/ise_ply.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::ise_extractor {

using ise::Cluster;
using ise::Ise;
using ise::RobotTypeSpec;
using ise::Viewpoint;
using robot::RobotKind;

namespace {

void read_type(ParamReader& p, const std::string& name, RobotTypeSpec& t) {
  p.optional(name + "_delta_pose_m", t.delta_pose_m, {0.01, 1000})
      .doc("δ_pose: a viewpoint's distance from its ISE (m; tables 5.3, 2.1)");
  p.optional(name + "_fov_h_deg", t.fov_h_deg, {1, 179})
      .doc("camera's horizontal field of view (degrees)");
  p.optional(name + "_fov_v_deg", t.fov_v_deg, {1, 179})
      .doc("camera's vertical field of view (degrees)");
  p.optional(name + "_min_range_m", t.min_range_m, {0.001, 1000})
      .doc("camera range: nearest depth (m)");
  p.optional(name + "_max_range_m", t.max_range_m, {0.01, 1000})
      .doc("camera range: farthest depth (m)");
  p.optional(name + "_clearance_m", t.clearance_m, {0, 100})
      .doc("the free radius a viewpoint needs (m; default the body's bounding radius)");
  p.optional(name + "_unknown_is_free", t.unknown_is_free)
      .doc("unknown voxels count as free in the clearance region");
  p.optional(name + "_viewpoint_in_unknown", t.viewpoint_in_unknown)
      .doc(
          "open air: the viewpoint's own voxel may be unknown, and gain rays cross unknown voxels");
  if (t.type == RobotKind::kMultirotor) {
    p.optional(name + "_min_altitude_m", t.min_altitude_m, {-1e4, 1e4})
        .doc("the low-level planner's altitude band, bottom: a lower candidate moves up to it (m)");
    p.optional(name + "_max_altitude_m", t.max_altitude_m, {-1e4, 1e4})
        .doc("the low-level planner's altitude band, top: a higher candidate moves down to it (m)");
  }
  if (t.type == RobotKind::kGround) {
    p.optional(name + "_camera_height_m", t.camera_height_m, {0.01, 100})
        .doc("ground robots: the camera's height above the floor (m)");
    p.optional(name + "_floor_z_m", t.floor_z_m, {-1e4, 1e4})
        .doc("ground robots: the floor's height (m)");
  }
}

msg::Vec3 vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

IseExtractor::Config IseExtractor::read_config(ParamReader& p) {
  Config c;
  // the per-type keys of both kinds are read (so a typo is reported as unknown) and used for
  // the kinds of the launch file's robots
  RobotTypeSpec ground;
  ground.type = RobotKind::kGround;
  RobotTypeSpec multirotor;
  multirotor.type = RobotKind::kMultirotor;
  // multirotor defaults: the powerplant UAV of table 2.1
  multirotor.delta_pose_m = 4.7;
  multirotor.min_range_m = 1.6;
  multirotor.max_range_m = 8.0;
  multirotor.clearance_m = robot::BodyModel::of(RobotKind::kMultirotor).bounding_radius_m();
  multirotor.unknown_is_free = true;
  read_type(p, "ground", ground);
  read_type(p, "multirotor", multirotor);
  c.ise.robot_types = {ground, multirotor};  // narrowed to the team's kinds on configure
  p.optional("merge_distance_m", c.ise.merge_distance_m, {0, 100})
      .doc(
          "ε: viewpoints closer than this (with directions within merge_angle_deg) are merged (m)");
  p.optional("merge_angle_deg", c.ise.merge_angle_deg, {0, 89.9})
      .doc("direction tolerance of the merge (degrees)");
  p.optional("d_v_m", c.ise.d_v_m, {0.01, 1000})
      .doc("d_v: a viewpoint joins a cluster when a member is within this (m; table 5.3)");
  p.optional("d_v_max_m", c.ise.d_v_max_m, {0.01, 1000})
      .doc(
          "d_v^max: a viewpoint with no neighbour within d_v joins its nearest one within this "
          "(m)");
  p.optional("gain_rows", c.ise.gain_rows, {1, 1000})
      .doc("gain rays per viewpoint: rows over the camera's FOV (odd: one along the optical axis)");
  p.optional("gain_cols", c.ise.gain_cols, {1, 1000})
      .doc("gain rays per viewpoint: columns over the camera's FOV");
  p.optional("completion_updates", c.ise.completion_updates, {1, 1000000})
      .doc("complete after this many consecutive updates with no inspectable ISE");
  std::vector<double> region_min, region_max;
  p.optional_list("region_min_m", region_min, 3, {-1e6, 1e6})
      .doc(
          "the box to reconstruct, lower corner [x, y, z] (world, m): ISEs outside are dropped; "
          "default everywhere");
  p.optional_list("region_max_m", region_max, 3, {-1e6, 1e6})
      .doc("the box to reconstruct, upper corner [x, y, z] (world, m)");
  if (region_min.size() == 3) c.ise.region_min_m = Eigen::Vector3d(region_min.data());
  if (region_max.size() == 3) c.ise.region_max_m = Eigen::Vector3d(region_max.data());
  if (!(c.ise.region_min_m.array() < c.ise.region_max_m.array()).all())
    p.report("region_max_m", "must be above region_min_m on every axis");
  p.optional("ply_path", c.ply_path)
      .doc(
          "a picture of the last result (coloured point cloud), written at stop (empty: not "
          "written)");
  p.optional("give_up_visits", c.give_up_visits, {0, 1000000})
      .doc(
          "an ISE still incomplete after this many visits is given up (0: never, the thesis; "
          "docs/ise.md)");
  p.optional("visit_distance_m", c.visit_distance_m, {0.01, 100})
      .doc("a robot this near a viewpoint (horizontally, for a ground viewpoint) stands at it (m)");
  p.optional("visit_angle_deg", c.visit_angle_deg, {0.1, 180})
      .doc("and its yaw this close to the viewpoint's (degrees)");
  p.optional("visit_period_s", c.visit_period_s, {0, 1000})
      .doc(
          "a stay at a viewpoint counts a visit on arrival and one more per this much time (s; 0: "
          "every update)");
  return c;
}

IseExtractor::IseExtractor(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> IseExtractor::on_configure() {
  // the kinds of the launch file's robots (a ground robot's without a team)
  uint32_t kinds = 0;
  for (const TeamMember& m : team()) kinds |= robot::kind_bit(m.kind);
  if (kinds == 0) kinds = robot::kind_bit(RobotKind::kGround);
  std::vector<RobotTypeSpec> types;
  for (const RobotTypeSpec& t : config_.ise.robot_types)
    if ((kinds & robot::kind_bit(t.type)) != 0) types.push_back(t);
  config_.ise.robot_types = types;
  // the map's W_th and voxel size come with the first snapshot; check the rest now
  if (std::string problem = config_.ise.validate(1.0, 1.0); !problem.empty())
    return make_unexpected(problem);
  ises_ = create_publisher<msg::IseSet>("ises", {.pool_size = 2});
  clusters_ = create_publisher<msg::ViewpointClusters>("clusters", {.pool_size = 2});
  create_subscription<msg::MapUpdate>("map", {.depth = 1},
                                      [this](Sample<msg::MapUpdate>&& s) { on_map(*s); });
  if (config_.give_up_visits > 0) {
    team_poses_.resize(team().size());
    stays_.resize(team().size());
    for (size_t i = 0; i < team().size(); ++i) {
      if (team()[i].ns.empty()) continue;
      create_teammate_subscription<msg::Odometry>(
          "pose", team()[i].ns, {.depth = 1}, [this, i](Sample<msg::Odometry>&& s) {
            const msg::Pose3& p = s->T_world_body;
            const double yaw = yaw_of(p.orientation);
            if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) ||
                !std::isfinite(p.position.z) || !std::isfinite(yaw))
              return;  // a bad pose counts no visit
            team_poses_[i] = {true, msg::to_eigen(p.position), yaw};
          });
      create_subscription<msg::Odometry>(
          "/" + team()[i].ns + "/skipped_goal", {.depth = 8}, [this](Sample<msg::Odometry>&& s) {
            const msg::Pose3& p = s->T_world_body;
            const double yaw = yaw_of(p.orientation);
            if (std::isfinite(p.position.x) && std::isfinite(p.position.y) &&
                std::isfinite(p.position.z) && std::isfinite(yaw))
              skipped_.push_back({true, msg::to_eigen(p.position), yaw});
          });
    }
  }
  return {};
}

// Every ISE that a viewpoint sees, or was made for, while a robot stands at it counts a
// visit: once when the robot arrives (its stay begins), and once more for every
// visit_period_s it stays; at give_up_visits it is given up (C_rem from the next update on).
// A stay ends when the robot moves visit_distance_m or turns visit_angle_deg from where it
// began. Counting per stay, not per map update, gives up after the same looks whatever the
// update rate (docs/ise.md, "Visited and still incomplete").
void IseExtractor::mark_looked(const IseResult& r, const RobotPose& pose, double max_angle_rad,
                               std::vector<uint8_t>& looked) const {
  for (const Viewpoint& v : r.viewpoints) {
    const Eigen::Vector3d d = v.position - pose.position;
    const double dist = v.type == RobotKind::kGround ? d.head<2>().norm() : d.norm();
    const double angle = std::abs(std::remainder(v.yaw_rad - pose.yaw_rad, 2 * M_PI));
    if (dist > config_.visit_distance_m || angle > max_angle_rad) continue;
    for (uint32_t id : v.seen) looked[id] = 1;
    for (uint32_t id : v.ises) looked[id] = 1;  // the ISEs it was made for
  }
}

void IseExtractor::count_visits(const IseResult& r, int64_t stamp_ns) {
  const double max_angle = config_.visit_angle_deg * M_PI / 180.0;
  // a tenth of the period early still counts: stamps jitter on hardware, and a look
  // 0.998 s after the last would otherwise wait for the next update
  constexpr double kEarly = 0.1;
  const auto period_ns =
      static_cast<int64_t>(std::llround((1.0 - kEarly) * config_.visit_period_s * 1e9));
  std::vector<VoxelIndex> give_up;
  std::vector<uint8_t> looked(r.ises.size(), 0);
  for (size_t k = 0; k < team_poses_.size(); ++k) {
    const RobotPose& pose = team_poses_[k];
    if (!pose.seen) continue;
    Stay& stay = stays_[k];
    if (!stay.active || (pose.position - stay.position).norm() > config_.visit_distance_m ||
        std::abs(std::remainder(pose.yaw_rad - stay.yaw_rad, 2 * M_PI)) > max_angle)
      stay = Stay{.active = true, .position = pose.position, .yaw_rad = pose.yaw_rad};
    std::fill(looked.begin(), looked.end(), 0);
    mark_looked(r, pose, max_angle, looked);
    for (uint32_t i = 0; i < r.ises.size(); ++i) {
      if (looked[i] == 0) continue;
      const VoxelIndex& voxel = r.ises[i].voxel;
      const auto [it, first] = stay.counted.try_emplace(voxel, stamp_ns);
      if (!first) {
        if (stamp_ns - it->second < period_ns) continue;
        it->second = stamp_ns;
      }
      if (++visits_[voxel] == config_.give_up_visits) give_up.push_back(voxel);
    }
  }
  // a skipped viewpoint: one visit for each ISE that the viewpoints there see or were made for
  for (const RobotPose& pose : skipped_) {
    std::fill(looked.begin(), looked.end(), 0);
    mark_looked(r, pose, max_angle, looked);
    for (uint32_t i = 0; i < r.ises.size(); ++i)
      if (looked[i] != 0 && ++visits_[r.ises[i].voxel] == config_.give_up_visits)
        give_up.push_back(r.ises[i].voxel);
  }
  skipped_.clear();
  if (give_up.empty()) return;
  pipeline_->give_up(give_up);
  SCANCREW_LOG_INFO(
      "%s: %zu ISEs seen from %d visited viewpoints and still incomplete: given up "
      "(C_rem; %zu in all)",
      qualified_name().c_str(), give_up.size(), config_.give_up_visits,
      pipeline_->given_up_count());
}

void IseExtractor::on_map(const msg::MapUpdate& update) {
  if (failed_ || update.map == nullptr) {
    skipped_.clear();  // counted at an update only: none will come, or none to count on
    return;
  }
  const tsdf::MapSnapshot& snap = *update.map;
  if (!pipeline_) {
    auto created = IsePipeline::create(config_.ise, snap.config().w_th, snap.voxel_m());
    if (!created) {
      failed_ = true;
      SCANCREW_LOG_ERROR("%s: %s (no ISEs will be published)", qualified_name().c_str(),
                         created.error().c_str());
      return;
    }
    pipeline_.emplace(std::move(created).value());
  }
  const IseResult& r = pipeline_->update(snap);
  if (config_.give_up_visits > 0) count_visits(r, update.header.stamp_ns);
  ++updates_;
  ms_sum_ += r.stats.total_ms;
  ms_max_ = std::max(ms_max_, r.stats.total_ms);
  stage_sum_.extract_ms += r.stats.extract_ms;
  stage_sum_.viewpoints_ms += r.stats.viewpoints_ms;
  stage_sum_.visibility_ms += r.stats.visibility_ms;
  stage_sum_.cluster_ms += r.stats.cluster_ms;
  stage_sum_.visibility_computed += r.stats.visibility_computed;
  stage_sum_.visibility_reused += r.stats.visibility_reused;
  publish(r, update.header.stamp_ns);
  if (r.complete && !completion_logged_) {
    completion_logged_ = true;
    SCANCREW_LOG_INFO(
        "%s: complete: no inspectable ISE over %d updates (%zu ISEs remain in "
        "C_rem)",
        qualified_name().c_str(), config_.ise.completion_updates, r.remaining.size());
  }
}

void IseExtractor::publish(const IseResult& r, int64_t stamp_ns) {
  if (auto loan = ises_.loan()) {
    msg::IseSet& m = **loan;
    m.header.stamp_ns = stamp_ns;
    m.map_version = r.map_sequence;
    m.centers_m.clear();
    m.view_directions.clear();
    for (const Ise& ise : r.ises) {
      m.centers_m.push_back(vec(ise.center));
      m.view_directions.push_back(vec(ise.direction));
    }
    m.remaining = r.remaining;
    m.inspectable = static_cast<uint32_t>(r.inspectable_count);
    m.complete = r.complete ? 1 : 0;
    (void)ises_.publish(std::move(*loan));
  }
  if (auto loan = clusters_.loan()) {
    msg::ViewpointClusters& m = **loan;
    m.header.stamp_ns = stamp_ns;
    m.map_version = r.map_sequence;
    m.ise_count = static_cast<uint32_t>(r.ises.size());
    m.clusters.clear();
    for (const Cluster& c : r.clusters) {
      msg::ViewpointCluster out;
      out.id = c.id;
      out.gain = c.gain;
      out.robot_types = c.types;
      out.centroid = vec(c.centroid);
      for (uint32_t i : c.viewpoints) {
        const Viewpoint& v = r.viewpoints[i];
        out.viewpoints.push_back(
            {.pose = {vec(v.position), v.yaw_rad}, .seen_ise = v.seen, .robot_types = v.types});
      }
      m.clusters.push_back(std::move(out));
    }
    (void)clusters_.publish(std::move(*loan));
  }
}

void IseExtractor::on_deactivate() {
  const IseResult* r = last();
  SCANCREW_LOG_INFO(
      "%s: %llu map updates (%.1f ms mean, %.1f max; in all %.0f ms extracting, %.0f "
      "viewpoints, %.0f visibility of %zu viewpoints (%zu reused), %.0f clusters); last: %zu "
      "ISEs, %zu in C_rem, %zu viewpoints, %zu clusters%s",
      qualified_name().c_str(), static_cast<unsigned long long>(updates_),
      updates_ > 0 ? ms_sum_ / static_cast<double>(updates_) : 0.0, ms_max_, stage_sum_.extract_ms,
      stage_sum_.viewpoints_ms, stage_sum_.visibility_ms, stage_sum_.visibility_computed,
      stage_sum_.visibility_reused, stage_sum_.cluster_ms, r ? r->ises.size() : 0,
      r ? r->remaining.size() : 0, r ? r->viewpoints.size() : 0, r ? r->clusters.size() : 0,
      r && r->complete ? ", complete" : "");
  if (r != nullptr && !config_.ply_path.empty()) {
    if (auto written = write_ise_ply(*r, config_.ply_path))
      SCANCREW_LOG_INFO("%s: wrote %s", qualified_name().c_str(), config_.ply_path.c_str());
    else
      report_failure(written.error());
  }
}

SCANCREW_REGISTER_COMPONENT(IseExtractor, "ise_extractor")

}  // namespace scancrew::ise_extractor
