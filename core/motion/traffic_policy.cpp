#include "core/motion/traffic_policy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace scancrew::motion {

TrafficConfig TrafficConfig::for_kind(RobotKind kind) {
  TrafficConfig c;
  c.kind = kind;
  if (kind == RobotKind::kMultirotor) c.d0_m = 1.0;  // collision radius, tables 2.1, 3.1, 4.1
  return c;
}

std::string TrafficConfig::validate() const {
  std::string e;
  auto add = [&e](const std::string& m) { e += (e.empty() ? "" : "; ") + m; };
  if (!(d0_m > 0)) add("d0_m must be > 0");
  if (!(k_s >= 0)) add("k_s must be >= 0");
  if (!(margin_m >= 0)) add("margin_m must be >= 0");
  if (!(frontal_angle_deg > 0 && frontal_angle_deg < 90))
    add("frontal_angle_deg must be in (0, 90)");
  if (!(tie_time_s >= 0)) add("tie_time_s must be >= 0");
  if (!(sample_step_m > 0)) add("sample_step_m must be > 0");
  if (!(aside_extra_m >= 0)) add("aside_extra_m must be >= 0");
  if (!(aside_step_m > 0)) add("aside_step_m must be > 0");
  if (!(aside_max_m >= aside_extra_m)) add("aside_max_m must be >= aside_extra_m");
  if (!(aside_min_move_m >= 0)) add("aside_min_move_m must be >= 0");
  if (!(fov_deg > 0 && fov_deg <= 360)) add("fov_deg must be in (0, 360]");
  if (!(max_wait_s > 0)) add("max_wait_s must be > 0");
  return e;
}

const char* to_string(TrafficAction action) {
  switch (action) {
    case TrafficAction::kProceed:
      return "proceed";
    case TrafficAction::kStopAndWait:
      return "stop_and_wait";
    case TrafficAction::kStepAside:
      return "step_aside";
    case TrafficAction::kResume:
      return "resume";
  }
  return "?";
}

const char* to_string(Encounter encounter) {
  switch (encounter) {
    case Encounter::kNone:
      return "none";
    case Encounter::kFrontal:
      return "frontal";
    case Encounter::kFollowing:
      return "following";
    case Encounter::kCrossing:
      return "crossing";
    case Encounter::kBlocking:
      return "blocking";
    case Encounter::kIntrusion:
      return "intrusion";
  }
  return "?";
}

namespace {

bool finite(const TrafficAgent& a) {
  if (!a.position.allFinite() || !a.velocity_mps.allFinite() || !std::isfinite(a.yaw_rad) ||
      !std::isfinite(a.nominal_speed_mps) || !std::isfinite(a.body_radius_m))
    return false;
  return std::all_of(a.path.begin(), a.path.end(),
                     [](const Eigen::Vector3d& p) { return p.allFinite(); });
}

double speed_of(const TrafficAgent& a, bool planar) {
  return planar ? a.velocity_mps.head<2>().norm() : a.velocity_mps.norm();
}

double nominal_of(const TrafficAgent& a) {
  return std::max(a.nominal_speed_mps, 1e-3);
}

double clearance(const TrafficAgent& a, const TrafficAgent& b, const TrafficConfig& c) {
  return std::max(a.body_radius_m, 0.0) + std::max(b.body_radius_m, 0.0) + c.margin_m;
}

// The first arc length along `from` (sampled every step) within `clear` of `to`; the arc
// length of the matching closest point of `to` in `to_s`.
bool entry(const Polyline& from, const Polyline& to, double clear, double step, double& from_s,
           double& to_s) {
  const double length = from.length_m();
  for (double s = 0;; s = std::min(s + step, length)) {
    const Polyline::Closest c = to.closest(from.at(s));
    if (c.distance_m < clear) {
      from_s = s;
      to_s = c.s_m;
      return true;
    }
    if (s >= length) return false;
  }
}

}  // namespace

PairConflict pair_conflict(const TrafficAgent& a, const TrafficAgent& b,
                           const TrafficConfig& config) {
  PairConflict pc;
  if (a.id == b.id || !finite(a) || !finite(b)) return pc;
  // canonical order: both robots of the pair compute the same numbers
  const TrafficAgent& first = a.id < b.id ? a : b;
  const TrafficAgent& second = a.id < b.id ? b : a;
  const bool planar = config.kind == RobotKind::kGround;
  // each path up to its robot's safety distance, at least the nominal speed's one: a robot
  // slowing down must not make the conflict flicker
  auto reach = [&](const TrafficAgent& x) {
    return config.safety_distance_m(std::max(speed_of(x, planar), nominal_of(x)));
  };
  const double clear = clearance(first, second, config);
  Polyline p1, p2;
  p1.assign(first.position, first.path, reach(first), planar);
  p2.assign(second.position, second.path, reach(second), planar);

  double s1 = 0, s2 = 0, on2 = 0, on1 = 0;
  const bool found1 = entry(p1, p2, clear, config.sample_step_m, s1, on2);
  const bool found2 = entry(p2, p1, clear, config.sample_step_m, s2, on1);
  if (!found1 && !found2) return pc;
  // sampling can miss a graze on one side: take the other side's closest point
  if (!found1) {
    s1 = on1;
    on2 = s2;
  }
  if (!found2) s2 = on2;
  pc.s_first_m = s1;
  pc.s_second_m = s2;

  const bool holding1 = p1.points().size() < 2;
  const bool holding2 = p2.points().size() < 2;
  if (holding1 && holding2) return pc;  // two parked robots: nothing to negotiate
  pc.found = true;
  if (holding1 || holding2) {
    pc.encounter = Encounter::kBlocking;
    pc.priority_id = holding1 ? second.id : first.id;
    return pc;
  }
  const Eigen::Vector3d t1 = p1.tangent(s1);
  const Eigen::Vector3d t2 = p2.tangent(on2);
  const double cos_angle = t1.dot(t2);
  const double cos_limit = std::cos(config.frontal_angle_deg * std::numbers::pi / 180.0);
  if (cos_angle < -cos_limit) {
    pc.encounter = Encounter::kFrontal;
    pc.priority_id = first.id;
  } else if (cos_angle > cos_limit) {
    pc.encounter = Encounter::kFollowing;
    const double ahead = (p2.points().front() - p1.points().front()).dot(t1);
    pc.priority_id = ahead > 0 ? second.id : first.id;
  } else {
    pc.encounter = Encounter::kCrossing;
    const double t_first = s1 / nominal_of(first);
    const double t_second = s2 / nominal_of(second);
    pc.priority_id = t_second + config.tie_time_s < t_first ? second.id : first.id;
  }
  return pc;
}

void TrafficPolicy::reset() {
  mode_ = Mode::kFree;
  held_by_ = 0;
  held_encounter_ = Encounter::kNone;
  replan_sent_ = false;
}

bool TrafficPolicy::in_view(const TrafficAgent& self, const TrafficAgent& other,
                            double range_m) const {
  const Eigen::Vector2d d = (other.position - self.position).head<2>();
  const double dist =
      config_.kind == RobotKind::kGround ? d.norm() : (other.position - self.position).norm();
  if (dist > range_m) return false;
  if (d.norm() < 1e-9) return true;
  const Eigen::Vector2d heading(std::cos(self.yaw_rad), std::sin(self.yaw_rad));
  const double angle = std::acos(std::clamp(heading.dot(d.normalized()), -1.0, 1.0));
  return angle <= 0.5 * config_.fov_deg * std::numbers::pi / 180.0;
}

// whether q is an aside point for self: free, reachable in a straight line, and `extra` beyond
// the clearance of every teammate's path (the priority robot's whole path, the others' up to
// the horizon)
bool TrafficPolicy::aside_fits(const Eigen::Vector3d& q, double extra, const TrafficAgent& self,
                               std::span<const TrafficAgent> teammates,
                               const TrafficAgent& priority, const FreeSpaceQuery& free) {
  const bool planar = config_.kind == RobotKind::kGround;
  auto horizon = [this](const TrafficAgent& x, const TrafficAgent& y) {
    return config_.safety_distance_m(nominal_of(x)) + config_.safety_distance_m(nominal_of(y));
  };
  const double step = config_.sample_step_m;
  auto segment_free = [&](const Eigen::Vector3d& to) {
    const double len = (to - self.position).norm();
    const int n_samples = static_cast<int>(std::ceil(len / step));
    for (int i = 1; i <= n_samples; ++i)
      if (!free(self.position + (to - self.position) * (static_cast<double>(i) / n_samples)))
        return false;
    return true;
  };
  // a point within the tracker's position tolerance would be "reached" without a move,
  // and the robot would stay in the way (the parking lot's distributed pair, 0.09 m)
  if ((q - self.position).norm() < config_.aside_min_move_m) return false;
  if (!free(q) || !segment_free(q)) return false;
  for (const TrafficAgent& j : teammates) {
    if (j.id == self.id || !finite(j)) continue;
    own_.assign(j.position, j.path,
                j.id == priority.id ? std::numeric_limits<double>::infinity() : horizon(self, j),
                planar);
    if (own_.closest(q).distance_m < clearance(self, j, config_) + extra) return false;
  }
  return true;
}

bool TrafficPolicy::find_aside_point(const TrafficAgent& self,
                                     std::span<const TrafficAgent> teammates,
                                     const TrafficAgent& priority, const FreeSpaceQuery& free,
                                     Eigen::Vector3d& aside) {
  if (!free) return false;
  const bool planar = config_.kind == RobotKind::kGround;
  // the priority robot's whole path: it will pass the aside point, however far ahead
  other_.assign(priority.position, priority.path, std::numeric_limits<double>::infinity(), planar);
  const Polyline::Closest c = other_.closest(self.position);
  const Eigen::Vector3d q0 = other_.at(c.s_m);
  Eigen::Vector3d u = other_.tangent(c.s_m);
  if (u.head<2>().norm() < 1e-9)
    u = Eigen::Vector3d(std::cos(priority.yaw_rad), std::sin(priority.yaw_rad), 0.0);
  Eigen::Vector3d n(-u.y(), u.x(), 0.0);
  n.normalize();
  // the side the robot is already on; on the path itself, its right (keep right)
  const double offset = (other_.project(self.position) - q0).dot(n);
  const Eigen::Vector3d right(std::sin(self.yaw_rad), -std::cos(self.yaw_rad), 0.0);
  const double side =
      std::abs(offset) > 0.01 ? (offset > 0 ? 1.0 : -1.0) : (n.dot(right) >= 0 ? 1.0 : -1.0);
  std::array<Eigen::Vector3d, 4> dirs = {side * n, -side * n, Eigen::Vector3d::UnitZ(),
                                         -Eigen::Vector3d::UnitZ()};
  const size_t dir_count = planar ? 2 : 4;

  const double clear = clearance(self, priority, config_);
  auto fits = [&](const Eigen::Vector3d& q, double extra) {
    return aside_fits(q, extra, self, teammates, priority, free);
  };
  const int lateral_count =
      static_cast<int>(
          std::floor((config_.aside_max_m - config_.aside_extra_m) / config_.aside_step_m + 1e-9)) +
      1;
  for (size_t d = 0; d < dir_count; ++d) {
    for (int i = 0; i < lateral_count; ++i) {
      const double lateral = clear + config_.aside_extra_m + i * config_.aside_step_m;
      Eigen::Vector3d q = q0 + dirs[d] * lateral;
      if (planar) q.z() = self.position.z();
      if (fits(q, 0.0)) {
        aside = q;
        return true;
      }
    }
  }
  // Neither side of the priority robot's path: an obstacle on one, the path itself on the
  // other (its goal right beside this robot: the parking lot's distributed pair held each
  // other for 300 s). Then any direction around the robot, nearest first, starting from
  // the preferred side, out to the same reach; as far from the paths as the lateral points
  // (aside_extra_m beyond the clearance).
  constexpr int kRingDirections = 16;
  const double side_angle = std::atan2(side * n.y(), side * n.x());
  const double reach = clear + config_.aside_max_m;
  for (double r = config_.aside_step_m; r <= reach + 1e-9; r += config_.aside_step_m) {
    for (int k = 0; k < kRingDirections; ++k) {
      const int turn = k % 2 == 0 ? k / 2 : -(k + 1) / 2;
      const double angle = side_angle + 2 * std::numbers::pi * turn / kRingDirections;
      const Eigen::Vector3d q =
          self.position + r * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
      if (fits(q, config_.aside_extra_m)) {
        aside = q;
        return true;
      }
    }
  }
  return false;
}

TrafficDecision TrafficPolicy::hold(TrafficAction action, const Candidate& c, double now_s) {
  TrafficDecision out;
  out.action = action;
  out.because_of_robot = c.robot;
  out.encounter = c.encounter;
  held_by_ = c.robot;
  held_encounter_ = c.encounter;
  if (action == TrafficAction::kStepAside) {
    out.aside_point = aside_;
    out.aside_yaw_rad = aside_yaw_;
  }
  out.held_s = std::max(0.0, now_s - hold_since_s_);
  if (out.held_s > config_.max_wait_s && !replan_sent_) {
    out.request_replan = true;
    replan_sent_ = true;
  }
  return out;
}

// Whether `self`'s body is on `k`'s way ahead: what k's safety net (below) stops k for.
// A yielder there that only stopped would hold k too, and both would wait: two robots side
// by side whose paths leave the same way (a following encounter, priority to the one a few
// centimetres ahead) held each other for 335 s in a parking-lot run (docs/traffic_policy.md,
// rule 8). So such a yielder steps aside instead.
bool TrafficPolicy::on_way_ahead_of(const TrafficAgent& k, const TrafficAgent& self) {
  const bool planar = config_.kind == RobotKind::kGround;
  other_.assign(k.position, k.path,
                config_.safety_distance_m(std::max(speed_of(k, planar), nominal_of(k))), planar);
  if (other_.points().size() < 2) return false;
  const bool ahead =
      (other_.project(self.position) - other_.points().front()).dot(other_.tangent(0)) > 0;
  return ahead && other_.closest(self.position).distance_m < clearance(self, k, config_);
}

// the reasons to yield to the teammates, own_ holding the way the robot is about to move
TrafficPolicy::Reasons TrafficPolicy::reasons(const TrafficAgent& self,
                                              std::span<const TrafficAgent> teammates,
                                              double reach) {
  const bool moving = own_.points().size() >= 2;
  const Eigen::Vector3d own_start = own_.points().front();
  const Eigen::Vector3d own_dir = own_.tangent(0);

  // the most urgent reason of each kind (smallest arc length, then lowest id)
  Reasons r;
  auto consider = [](const Candidate& c, Candidate& best, bool& want) {
    if (!want || c.s_m < best.s_m || (c.s_m == best.s_m && c.robot < best.robot)) best = c;
    want = true;
  };
  for (const TrafficAgent& k : teammates) {
    if (k.id == self.id || !finite(k)) continue;
    const PairConflict pc = pair_conflict(self, k, config_);
    if (pc.found && pc.priority_id != self.id) {
      const double s_self = pc.s_of(self.id, std::min(self.id, k.id));
      if (s_self <= reach) {
        const bool inside = s_self < 0.5 * config_.sample_step_m;
        const bool aside =
            pc.encounter == Encounter::kFrontal || pc.encounter == Encounter::kBlocking ||
            (pc.encounter == Encounter::kCrossing && inside) || on_way_ahead_of(k, self);
        if (aside)
          consider({TrafficAction::kStepAside, pc.encounter, k.id, s_self}, r.aside, r.want_aside);
        else
          consider({TrafficAction::kStopAndWait, pc.encounter, k.id, s_self}, r.stop, r.want_stop);
      }
    }
    // safety net: a body on the way ahead stops the robot, whatever the priority
    if (moving) {
      const Polyline::Closest c = own_.closest(k.position);
      const bool ahead = (own_.project(k.position) - own_start).dot(own_dir) > 0;
      if (ahead && c.distance_m < clearance(self, k, config_))
        consider({TrafficAction::kStopAndWait, Encounter::kIntrusion, k.id, c.s_m}, r.net,
                 r.want_net);
    }
  }
  return r;
}

// the hold the reasons call for (stepping aside, or stopping), switching mode; nothing when
// they call for none
std::optional<TrafficDecision> TrafficPolicy::decide(const Reasons& r, const TrafficAgent& self,
                                                     std::span<const TrafficAgent> teammates,
                                                     const FreeSpaceQuery& free, double now_s) {
  if (mode_ == Mode::kAside) {
    if (r.want_aside || r.want_stop) {
      // still yielding: go to (or stay at) the aside point, pausing while a body is on the way
      if (r.want_net) return hold(TrafficAction::kStopAndWait, r.net, now_s);
      return hold(TrafficAction::kStepAside, r.want_aside ? r.aside : r.stop, now_s);
    }
  } else {
    if (r.want_aside) {
      const auto it = std::find_if(teammates.begin(), teammates.end(),
                                   [&](const TrafficAgent& k) { return k.id == r.aside.robot; });
      Eigen::Vector3d q;
      if (find_aside_point(self, teammates, *it, free, q)) {
        mode_ = Mode::kAside;
        aside_ = q;
        aside_yaw_ = self.yaw_rad;
        return hold(TrafficAction::kStepAside, r.aside, now_s);
      }
      mode_ = Mode::kWaiting;
      TrafficDecision out = hold(TrafficAction::kStopAndWait, r.aside, now_s);
      out.no_aside_point = true;
      return out;
    }
    if (r.want_stop || r.want_net) {
      mode_ = Mode::kWaiting;
      const bool net_first =
          !r.want_stop || (r.want_net && (r.net.s_m < r.stop.s_m ||
                                          (r.net.s_m == r.stop.s_m && r.net.robot < r.stop.robot)));
      return hold(TrafficAction::kStopAndWait, net_first ? r.net : r.stop, now_s);
    }
  }
  return std::nullopt;
}

TrafficDecision TrafficPolicy::update(const TrafficAgent& self,
                                      std::span<const TrafficAgent> teammates,
                                      const FreeSpaceQuery& free, double now_s) {
  const bool planar = config_.kind == RobotKind::kGround;
  const bool was_free = mode_ == Mode::kFree;
  if (was_free) {
    hold_since_s_ = now_s;
    replan_sent_ = false;
  }
  if (!finite(self)) {
    // no trustworthy own state: hold
    mode_ = Mode::kWaiting;
    return hold(TrafficAction::kStopAndWait, {}, now_s);
  }
  // act within d(v); once holding, stay until clear at nominal speed (hysteresis)
  const double reach =
      config_.safety_distance_m(was_free ? speed_of(self, planar) : nominal_of(self));
  // the way the robot is about to move: to its aside point, or along its path
  if (mode_ == Mode::kAside)
    own_.assign(self.position, std::span<const Eigen::Vector3d>(&aside_, 1),
                std::numeric_limits<double>::infinity(), planar);
  else
    own_.assign(self.position, self.path, reach, planar);

  const Reasons r = reasons(self, teammates, reach);
  if (std::optional<TrafficDecision> held = decide(r, self, teammates, free, now_s)) return *held;
  if (mode_ == Mode::kFree) return {};
  // after a crossing: until the teammate leaves the field of view (or is far enough)
  if (mode_ == Mode::kWaiting && held_encounter_ == Encounter::kCrossing &&
      config_.wait_until_out_of_view) {
    const auto it = std::find_if(teammates.begin(), teammates.end(),
                                 [&](const TrafficAgent& k) { return k.id == held_by_; });
    if (it != teammates.end() && finite(*it) &&
        in_view(self, *it,
                config_.safety_distance_m(nominal_of(self)) + clearance(self, *it, config_)))
      return hold(TrafficAction::kStopAndWait,
                  {TrafficAction::kStopAndWait, Encounter::kCrossing, held_by_, 0.0}, now_s);
  }
  TrafficDecision out;
  out.action = TrafficAction::kResume;
  out.because_of_robot = held_by_;
  out.encounter = held_encounter_;
  out.held_s = std::max(0.0, now_s - hold_since_s_);
  reset();
  return out;
}

}  // namespace scancrew::motion
