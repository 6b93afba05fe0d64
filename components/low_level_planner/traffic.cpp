// The LowLevelPlanner and its teammates: the traffic policy's view of them (TrafficAgent),
// its decision on the robot's path, an idle robot making way, lost teammates parked in the
// motion planner.

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "components/low_level_planner/local_path.hpp"
#include "components/low_level_planner/low_level_planner.hpp"
#include "core/motion/map_queries.hpp"
#include "executors/log.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::low_level_planner {

using motion::aside_on_the_way;
using motion::free_space_query;
using motion::FreeSpaceQuery;
using motion::FreeSpaceSpec;

namespace {

using Mode = msg::RobotState::Mode;

// slower than this, a teammate off kMoving is taken as holding its place (m/s)
constexpr double kMovingSpeedMps = 0.05;

}  // namespace

// A lost teammate never moves again: the planner keeps the body clear of it, so that a
// path is planned round it (the traffic policy would hold the robot behind it for good;
// the split arena team ran out of time with robot 1 held 1.1 m behind killed robot 3).
void LowLevelPlanner::park_lost_teammates() {
  if (!planner_) return;
  std::vector<Eigen::Vector3d> centers;
  double radius = 0;
  for (const Teammate& t : teammates_)
    if (t.seen && t.state.mode == Mode::kLost) {
      centers.push_back(msg::to_eigen(t.state.T_world_body.position));
      radius = std::max(radius, t.traffic_radius_m);
    }
  planner_->set_parked(std::move(centers), radius);
}

TrafficAgent LowLevelPlanner::self_agent() const {
  TrafficAgent a;
  a.id = robot_id();
  a.position = msg::to_eigen(pose_->T_world_body.position);
  a.yaw_rad = yaw_of(pose_->T_world_body.orientation);
  a.velocity_mps = msg::to_eigen(pose_->linear_velocity_mps);
  a.nominal_speed_mps = nominal_speed_mps_;
  a.body_radius_m = traffic_radius_m_;
  return a;
}

// The traffic policy's decision for this robot on `path` (its remaining local path; empty
// for a robot holding its place) against every teammate's broadcast state.
TrafficDecision LowLevelPlanner::traffic_decision(std::vector<Eigen::Vector3d> path) {
  std::vector<TrafficAgent> others;
  for (const Teammate& t : teammates_) {
    // a lost teammate is still there (a dead process leaves its robot where it stood, and
    // the depth mask blanked it out of the maps until then): it holds its place
    if (!t.seen) continue;
    TrafficAgent a;
    a.id = t.id;
    a.position = msg::to_eigen(t.state.T_world_body.position);
    a.yaw_rad = yaw_of(t.state.T_world_body.orientation);
    a.velocity_mps = msg::to_eigen(t.state.velocity_mps);
    a.nominal_speed_mps = t.nominal_speed_mps;
    a.body_radius_m = t.traffic_radius_m;
    // a teammate still on its last path (it may be waiting for a plan, or held by the
    // traffic policy, meanwhile) has the rest of it ahead; one at rest off a path holds its
    // place. (A held teammate read as parked made a deadlock: it waited for an idle robot in
    // its way, which saw two parked robots and nothing to negotiate.)
    const bool moving = t.state.mode == Mode::kMoving || t.state.mode == Mode::kWaiting ||
                        a.velocity_mps.norm() > kMovingSpeedMps;
    if (moving) a.path = remaining_path(t.local_path, a.position);
    others.push_back(std::move(a));
  }
  TrafficAgent me = self_agent();
  me.path = std::move(path);  // empty: the robot reads as holding its place
  FreeSpaceSpec spec;
  spec.kind = checks_.obstacle.kind;
  spec.body_radius_m = me.body_radius_m;
  spec.min_height_m = checks_.obstacle.min_height_m;
  spec.max_height_m = checks_.obstacle.max_height_m;
  const FreeSpaceQuery free = map_ ? free_space_query(map_, spec) : FreeSpaceQuery{};
  TrafficDecision d = traffic_->update(me, others, free, now_s());
  log_traffic(d);
  return d;
}

void LowLevelPlanner::log_traffic(const TrafficDecision& d) {
  if (log::threshold() < log::Level::kDebug) return;
  const bool new_aside = d.action == TrafficAction::kStepAside &&
                         (d.aside_point - last_traffic_.aside_point).norm() > 0.05;
  if (d.action == last_traffic_.action && d.encounter == last_traffic_.encounter &&
      d.because_of_robot == last_traffic_.because_of_robot && !new_aside)
    return;
  last_traffic_ = d;
  const msg::Vec3& p = pose_->T_world_body.position;
  std::string mates;
  for (const Teammate& t : teammates_) {
    if (!t.seen) continue;
    const msg::Vec3& q = t.state.T_world_body.position;
    char buf[96];
    std::snprintf(buf, sizeof buf, " r%u %s at (%.2f, %.2f) %.2f m", t.id,
                  msg::to_string(t.state.mode), q.x, q.y, std::hypot(q.x - p.x, q.y - p.y));
    mates += buf;
  }
  char to[48] = "";
  if (d.action == TrafficAction::kStepAside)
    std::snprintf(to, sizeof to, " to (%.2f, %.2f)", d.aside_point.x(), d.aside_point.y());
  SCANCREW_LOG_DEBUG(
      "%s: t %.1f s traffic %s%s%s (%s, robot %u, held %.1f s) at (%.2f, %.2f), mode %s;%s",
      qualified_name().c_str(), now_s(), to_string(d.action), to,
      d.no_aside_point ? " (no aside point)" : "", to_string(d.encounter), d.because_of_robot,
      d.held_s, p.x, p.y, msg::to_string(mode_), mates.c_str());
}

// An idle robot holds its place; when it blocks a teammate's way (traffic rule "blocking":
// the holding robot steps aside, docs/traffic_policy.md) it steps aside and stays at the
// aside point until its next path (plan_to_goal's kResume): a resume as soon as the policy
// sees the way clear stopped it half-way, back within the teammate's clearance. Before this,
// only a moving robot ran the policy, and a teammate whose goal lay past an idle robot
// waited for it for ever (the parking lot's 3-robot centralized team, seed 2).
// Once there (within GoalReached's tolerance, or after max_wait_s on the way), it looks
// again: a teammate whose path has changed since may still find it in the way (the parking
// lot's distributed pair: robot 2 held for 300 s beside robot 1 at its first aside point).
void LowLevelPlanner::make_way() {
  if (!config_.traffic_policy || teammates_.empty() || !map_) return;
  if (last_maneuver_ == msg::Maneuver::Kind::kStepAside) {
    if (!aside_sent_) return;
    if (aside_on_the_way(checks_.obstacle.kind, msg::to_eigen(pose_->T_world_body.position),
                         aside_sent_->point, now_s() - aside_sent_->at_s, checks_.goal,
                         checks_.traffic.max_wait_s))
      return;           // on the way
    traffic_->reset();  // from here, a new aside point if still in the way
  }
  const TrafficDecision d = traffic_decision({});
  if (d.action != TrafficAction::kStepAside) return;
  ++stats_.traffic_holds;
  aside_sent_ = AsideSent{.point = d.aside_point, .at_s = now_s()};
  send_maneuver(msg::Maneuver::Kind::kStepAside,
                {.position = msg::to_msg(d.aside_point), .yaw_rad = d.aside_yaw_rad},
                d.because_of_robot);
}

}  // namespace scancrew::low_level_planner
