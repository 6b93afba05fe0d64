#pragma once

// A small deterministic kinematic simulation for the traffic-policy tests: ground robots as
// unicycles (turn in place, forward speed and yaw rate limited, acceleration limited),
// aerial robots as holonomic points, integrated at a fixed dt. Each tick every robot's
// TrafficPolicy sees the others' states of that tick (perfect, instantaneous sharing) and
// its maneuver drives a simple tracker: follow the waypoints, hold, go to the aside point,
// and back to the path on kResume. No MuJoCo, no randomness.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "core/motion/goal_check.hpp"
#include "core/motion/traffic_policy.hpp"

namespace scancrew::motion::test {

struct SimLimits {
  double dt_s = 0.05;
  double accel_mps2 = 1.0;
  double max_yaw_rate_radps = 1.5;
  double yaw_gain = 2.5;           // 1/s
  double turn_in_place_rad = 0.6;  // heading errors above this: turn before driving
  double waypoint_radius_m = 0.1;
};

struct SimRobot {
  SimRobot(uint32_t id, RobotKind kind, const Eigen::Vector3d& start, double yaw,
           std::vector<Eigen::Vector3d> waypoints, TrafficConfig config)
      : kind(kind), waypoints(std::move(waypoints)), policy(config) {
    agent.id = id;
    agent.position = start;
    agent.yaw_rad = yaw;
    agent.nominal_speed_mps = kind == RobotKind::kGround ? 0.5 : 0.6;
  }

  RobotKind kind;
  TrafficAgent agent;
  std::vector<Eigen::Vector3d> waypoints;
  size_t next = 0;
  double speed = 0;  // ground: forward speed
  TrafficPolicy policy;

  // the current maneuver
  TrafficAction mode = TrafficAction::kProceed;
  Eigen::Vector3d aside = Eigen::Vector3d::Zero();

  // what happened
  int goal_tick = -1;
  int stop_ticks = 0, aside_ticks = 0, resumes = 0, replan_requests = 0;
  bool waited_for_crossing = false, stepped_aside = false;
  double travelled_m = 0;

  bool done() const { return next >= waypoints.size(); }
  void refresh_path() {
    agent.path.assign(
        waypoints.begin() + static_cast<std::ptrdiff_t>(std::min(next, waypoints.size())),
        waypoints.end());
  }
};

inline double approach(double v, double target, double max_step) {
  return v + std::clamp(target - v, -max_step, max_step);
}

// One tick of one robot's tracker after its decision.
inline void drive(SimRobot& r, const SimLimits& lim) {
  const double dt = lim.dt_s;
  Eigen::Vector3d target = r.agent.position;
  bool go = false;
  double cruise = r.agent.nominal_speed_mps;
  if (r.mode == TrafficAction::kStepAside) {
    target = r.aside;
    go = true;
  } else if (r.mode != TrafficAction::kStopAndWait && !r.done()) {
    target = r.waypoints[r.next];
    go = true;
  }
  const Eigen::Vector3d before = r.agent.position;
  if (r.kind == RobotKind::kGround) {
    const Eigen::Vector2d d = (target - r.agent.position).head<2>();
    double v_des = 0, w = 0;
    if (go && d.norm() > 0.02) {
      const double err = wrap_angle(std::atan2(d.y(), d.x()) - r.agent.yaw_rad);
      w = std::clamp(lim.yaw_gain * err, -lim.max_yaw_rate_radps, lim.max_yaw_rate_radps);
      const bool last = r.mode == TrafficAction::kStepAside || r.next + 1 >= r.waypoints.size();
      const double brake = std::sqrt(2 * lim.accel_mps2 * d.norm());  // stop at the target
      v_des =
          std::abs(err) > lim.turn_in_place_rad ? 0.0 : (last ? std::min(cruise, brake) : cruise);
    }
    r.speed = approach(r.speed, v_des, lim.accel_mps2 * dt);
    r.agent.yaw_rad = wrap_angle(r.agent.yaw_rad + w * dt);
    const Eigen::Vector3d heading(std::cos(r.agent.yaw_rad), std::sin(r.agent.yaw_rad), 0);
    r.agent.velocity_mps = heading * r.speed;
  } else {
    const Eigen::Vector3d d = target - r.agent.position;
    Eigen::Vector3d v_des = Eigen::Vector3d::Zero();
    if (go && d.norm() > 0.02) {
      const double brake = std::sqrt(2 * lim.accel_mps2 * d.norm());
      v_des = d.normalized() * std::min(cruise, brake);
    }
    const Eigen::Vector3d dv = v_des - r.agent.velocity_mps;
    const double max_dv = lim.accel_mps2 * dt;
    r.agent.velocity_mps += dv.norm() > max_dv ? Eigen::Vector3d(dv.normalized() * max_dv) : dv;
    if (r.agent.velocity_mps.head<2>().norm() > 1e-3)
      r.agent.yaw_rad = std::atan2(r.agent.velocity_mps.y(), r.agent.velocity_mps.x());
  }
  r.agent.position += r.agent.velocity_mps * dt;
  r.travelled_m += (r.agent.position - before).norm();
  // waypoints pass while following the path only
  if (r.mode != TrafficAction::kStepAside && r.mode != TrafficAction::kStopAndWait && !r.done() &&
      goal_distance_m(r.kind, r.agent.position, r.waypoints[r.next]) < lim.waypoint_radius_m)
    ++r.next;
}

struct SimOutcome {
  int ticks = 0;
  double min_separation_m = std::numeric_limits<double>::infinity();  // centre to centre
  bool all_done = false;
};

// Runs until every robot reached its last waypoint or max_ticks. `free` is every robot's
// free-space query (the same world for all).
// `trace`: print every change of maneuver (debugging).
inline SimOutcome run(std::vector<SimRobot>& robots, const FreeSpaceQuery& free, int max_ticks,
                      const SimLimits& lim = {}, bool trace = false) {
  SimOutcome out;
  std::vector<TrafficAgent> others;
  for (int tick = 0; tick < max_ticks; ++tick) {
    for (SimRobot& r : robots) r.refresh_path();
    // decisions on the states of this tick
    std::vector<TrafficDecision> decisions;
    decisions.reserve(robots.size());
    for (SimRobot& r : robots) {
      others.clear();
      for (const SimRobot& o : robots)
        if (o.agent.id != r.agent.id) others.push_back(o.agent);
      decisions.push_back(r.policy.update(r.agent, others, free, tick * lim.dt_s));
    }
    for (size_t i = 0; i < robots.size(); ++i) {
      SimRobot& r = robots[i];
      const TrafficDecision& d = decisions[i];
      if (d.request_replan) ++r.replan_requests;
      if (trace && (d.action != r.mode || d.request_replan))
        std::printf("t=%.2f robot %u at (%.2f, %.2f) v=%.2f: %s because of %u (%s)%s\n",
                    tick * lim.dt_s, r.agent.id, r.agent.position.x(), r.agent.position.y(),
                    r.agent.velocity_mps.norm(), to_string(d.action), d.because_of_robot,
                    to_string(d.encounter), d.request_replan ? " replan" : "");
      switch (d.action) {
        case TrafficAction::kProceed:
          break;
        case TrafficAction::kResume:
          ++r.resumes;
          r.mode = TrafficAction::kProceed;
          break;
        case TrafficAction::kStopAndWait:
          ++r.stop_ticks;
          if (d.encounter == Encounter::kCrossing) r.waited_for_crossing = true;
          r.mode = TrafficAction::kStopAndWait;
          break;
        case TrafficAction::kStepAside:
          ++r.aside_ticks;
          r.stepped_aside = true;
          r.mode = TrafficAction::kStepAside;
          r.aside = d.aside_point;
          break;
      }
      drive(r, lim);
      if (r.done() && r.goal_tick < 0) r.goal_tick = tick + 1;
    }
    for (size_t i = 0; i < robots.size(); ++i)
      for (size_t j = i + 1; j < robots.size(); ++j) {
        const Eigen::Vector3d d = robots[i].agent.position - robots[j].agent.position;
        const double sep = robots[i].kind == RobotKind::kGround ? d.head<2>().norm() : d.norm();
        if (sep < out.min_separation_m && trace)
          std::printf("t=%.2f separation %u-%u %.3f m\n", tick * lim.dt_s, robots[i].agent.id,
                      robots[j].agent.id, sep);
        out.min_separation_m = std::min(out.min_separation_m, sep);
      }
    out.ticks = tick + 1;
    if (std::all_of(robots.begin(), robots.end(), [](const SimRobot& r) { return r.done(); })) {
      out.all_done = true;
      break;
    }
  }
  return out;
}

}  // namespace scancrew::motion::test
