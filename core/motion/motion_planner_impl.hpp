#pragma once

// MotionPlanner::Impl: the planner's state behind the pimpl — the OMPL space and LazyPRM*,
// the collision map, the roadmap's bounds and parked teammates — and the helpers they
// share. Private to core/motion (motion_planner.cpp, motion_planner_query.cpp): OMPL and
// FCL headers stay out of motion_planner.hpp.

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/base/spaces/SO2StateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <unordered_set>
#include <utility>

#include "core/motion/collision_map.hpp"
#include "core/motion/guide_path.hpp"
#include "core/motion/motion_planner.hpp"
#include "core/motion/reusable_lazy_prm.hpp"

namespace scancrew::motion {

namespace ob = ompl::base;
namespace og = ompl::geometric;

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Yaw's weight in the multirotor's state distance (OMPL's SE(2) weighs it the same way).
inline constexpr double kYawWeight = 0.5;

// Uniform samples that are free: the centre voxel is free (or unknown when unknown space
// does not collide), then the body's FCL test. LazyPRM* adds samples unchecked, and in a
// map that is mostly unknown or solid most uniform samples would only be found invalid
// later, each after an A* search over the roadmap (measured on the parking lot: first
// queries of 0.7 s and more). So vertices are checked when sampled; edges stay lazy, which
// is where LazyPRM saves (an edge costs length / collision_check_step_m body tests). After
// kSampleTries rejections the last sample is kept (and checked lazily).
class PlausibleStateSampler : public ob::StateSampler {
 public:
  static constexpr int kSampleTries = 100;
  PlausibleStateSampler(const ob::StateSpace* space,
                        std::function<bool(const ob::State*)> plausible)
      : ob::StateSampler(space),
        base_(space->allocDefaultStateSampler()),
        plausible_(std::move(plausible)) {}
  void sampleUniform(ob::State* s) override {
    for (int i = 0; i < kSampleTries; ++i) {
      base_->sampleUniform(s);
      if (plausible_(s)) return;
    }
  }
  void sampleUniformNear(ob::State* s, const ob::State* near, double distance) override {
    base_->sampleUniformNear(s, near, distance);
  }
  void sampleGaussian(ob::State* s, const ob::State* mean, double stddev) override {
    base_->sampleGaussian(s, mean, stddev);
  }

 private:
  ob::StateSamplerPtr base_;
  std::function<bool(const ob::State*)> plausible_;
};

inline bool finite(const msg::Waypoint& w) {
  return std::isfinite(w.position.x) && std::isfinite(w.position.y) &&
         std::isfinite(w.position.z) && std::isfinite(w.yaw_rad);
}

inline void configure_ompl_once(uint64_t seed) {
  static std::once_flag once;
  std::call_once(once, [seed] {
    ompl::msg::setLogLevel(ompl::msg::LOG_NONE);  // statuses say what went wrong
    if (seed != 0) ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(seed));
  });
}

struct MotionPlanner::Impl {
  PlannerConfig config;
  robot::BodyModel body;
  CollisionMap map;
  int64_t map_stamp_ns = 0;
  ob::StateSpacePtr space;
  ob::SpaceInformationPtr si;
  std::shared_ptr<ReusableLazyPrmStar> planner;
  std::shared_ptr<ob::PathLengthOptimizationObjective> objective;
  Eigen::AlignedBox3d bounds;  // the sampling box (grows only)
  std::optional<std::pair<PlanStatus, msg::Waypoint>> last_logged;
  std::optional<GuideGrid> guide;  // of the current map and bounds, built on first use

  explicit Impl(const PlannerConfig& c)
      : config(c), body(body_of(c)), map(body, c.unknown_is_occupied) {
    if (ground()) {
      space = std::make_shared<ob::SE2StateSpace>();
    } else {
      auto compound = std::make_shared<ob::CompoundStateSpace>();
      compound->addSubspace(std::make_shared<ob::RealVectorStateSpace>(3), 1.0);
      compound->addSubspace(std::make_shared<ob::SO2StateSpace>(), kYawWeight);
      compound->lock();
      space = compound;
    }
    // provisional bounds until the first map
    bounds = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
    apply_bounds();
    space->setStateSamplerAllocator([this](const ob::StateSpace* sp) {
      return std::make_shared<PlausibleStateSampler>(sp, [this](const ob::State* s) {
        const Eigen::Isometry3d T_world_body = pose_of(s);
        const tsdf::VoxelState v = map.state_at(T_world_body.translation());
        const bool plausible = v == tsdf::VoxelState::kEmpty ||
                               (v == tsdf::VoxelState::kUnknown && !config.unknown_is_occupied);
        return plausible && !map.collides(T_world_body);
      });
    });
    si = std::make_shared<ob::SpaceInformation>(space);
    si->setStateValidityChecker([this](const ob::State* s) { return valid(pose_of(s)); });
    si->setup();
    set_check_resolution();
    objective = std::make_shared<ob::PathLengthOptimizationObjective>(si);
    planner = std::make_shared<ReusableLazyPrmStar>(si);
  }

  bool ground() const { return config.robot_kind == RobotKind::kGround; }

  // --- states and poses ---
  Eigen::Isometry3d pose_of(const ob::State* s) const {
    double x = 0, y = 0, z = config.ground_body.safety_center_z_m, yaw = 0;
    if (ground()) {
      const auto* st = s->as<ob::SE2StateSpace::StateType>();
      x = st->getX();
      y = st->getY();
      yaw = st->getYaw();
    } else {
      const auto* cs = s->as<ob::CompoundState>();
      const double* v = cs->as<ob::RealVectorStateSpace::StateType>(0)->values;
      x = v[0];
      y = v[1];
      z = v[2];
      yaw = cs->as<ob::SO2StateSpace::StateType>(1)->value;
    }
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
    T_world_body.translation() = Eigen::Vector3d(x, y, z);
    T_world_body.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T_world_body;
  }
  Eigen::Vector3d center_of(const msg::Waypoint& w) const {
    return {w.position.x, w.position.y,
            ground() ? config.ground_body.safety_center_z_m : w.position.z};
  }
  Eigen::Isometry3d pose_of(const msg::Waypoint& w) const {
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
    T_world_body.translation() = center_of(w);
    T_world_body.linear() =
        Eigen::AngleAxisd(w.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T_world_body;
  }
  void set_state(ob::State* s, const msg::Waypoint& w) const {
    if (ground()) {
      auto* st = s->as<ob::SE2StateSpace::StateType>();
      st->setXY(w.position.x, w.position.y);
      st->setYaw(w.yaw_rad);
    } else {
      auto* cs = s->as<ob::CompoundState>();
      double* v = cs->as<ob::RealVectorStateSpace::StateType>(0)->values;
      v[0] = w.position.x;
      v[1] = w.position.y;
      v[2] = w.position.z;
      cs->as<ob::SO2StateSpace::StateType>(1)->value = w.yaw_rad;
    }
    space->enforceBounds(s);  // yaw into [-pi, pi)
  }
  msg::Waypoint waypoint_of(const ob::State* s, double ground_z) const {
    const Eigen::Isometry3d T_world_body = pose_of(s);
    msg::Waypoint w;
    w.position = {T_world_body.translation().x(), T_world_body.translation().y(),
                  ground() ? ground_z : T_world_body.translation().z()};
    const Eigen::Matrix3d rotation = T_world_body.linear();
    w.yaw_rad = std::atan2(rotation(1, 0), rotation(0, 0));
    return w;
  }

  // --- bounds ---
  void apply_bounds() {
    if (ground()) {
      ob::RealVectorBounds b(2);
      for (unsigned i = 0; i < 2; ++i) {
        b.setLow(i, bounds.min()[i]);
        b.setHigh(i, bounds.max()[i]);
      }
      space->as<ob::SE2StateSpace>()->setBounds(b);
    } else {
      ob::RealVectorBounds b(3);
      for (unsigned i = 0; i < 3; ++i) {
        b.setLow(i, bounds.min()[i]);
        b.setHigh(i, bounds.max()[i]);
      }
      space->as<ob::CompoundStateSpace>()->as<ob::RealVectorStateSpace>(0)->setBounds(b);
    }
  }
  // The longest motion checked at one state: collision_check_step_m, as a fraction of the
  // space's extent (which changes with the bounds). The yaw (SO(2), extent pi) gets its own
  // step, collision_check_step_m / the body's bounding radius: a rotation by it moves no
  // point of the body further than the step. With the whole space's fraction the yaw was
  // checked every ~0.01 rad on a parking-lot map (a 6 mm move of the ellipse's tip), and
  // rotating edges cost hundreds of checks.
  void set_check_resolution() {
    const double extent = space->getMaximumExtent();
    si->setStateValidityCheckingResolution(
        std::min(1.0, config.collision_check_step_m / std::max(extent, 1e-9)));
    space->setup();
    // a sphere is the same at any yaw: its yaw needs no intermediate checks
    const double lever_m = std::abs(body.safety_radii_m.x() - body.safety_radii_m.y()) > 1e-9
                               ? body.bounding_radius_m()
                               : 0.0;
    const double yaw_step = lever_m > 0 ? config.collision_check_step_m / lever_m
                                        : std::numeric_limits<double>::infinity();
    const ob::StateSpacePtr& yaw = space->as<ob::CompoundStateSpace>()->getSubspace(1);
    // OMPL takes a fraction in (0, 1)
    yaw->setLongestValidSegmentFraction(std::min(0.999, yaw_step / yaw->getMaximumExtent()));
    yaw->setup();
  }
  // Grows the sampling box to hold `box` (plus the margin; a multirotor's z clipped to its
  // altitudes).
  void grow_bounds(Eigen::AlignedBox3d box) {
    if (box.isEmpty()) return;
    box.min().array() -= config.bounds_margin_m;
    box.max().array() += config.bounds_margin_m;
    if (!ground()) {
      box.min().z() = std::max(box.min().z(), config.multirotor_min_altitude_m);
      box.max().z() = std::min(box.max().z(), config.multirotor_max_altitude_m);
      if (box.min().z() >= box.max().z()) return;
    }
    const Eigen::AlignedBox3d grown = map_bounds_set ? bounds.merged(box) : box;
    if (grown.isApprox(bounds) && map_bounds_set) return;
    bounds = grown;
    map_bounds_set = true;
    apply_bounds();
    set_check_resolution();
  }
  bool map_bounds_set = false;

  // --- teammates parked for good (set_parked) ---
  std::vector<Eigen::Vector3d> parked;
  double parked_radius_m = 0;
  // Centre distance: in the plane for a ground robot (its body's z is not the teammate's).
  double gap(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return ground() ? (a - b).head<2>().norm() : (a - b).norm();
  }
  bool clear_of_parked(const Eigen::Vector3d& c) const {
    const double clearance = body.bounding_radius_m() + parked_radius_m;
    return std::all_of(parked.begin(), parked.end(),
                       [&](const Eigen::Vector3d& p) { return gap(c, p) >= clearance; });
  }
  // Resets the roadmap's cached validity of the vertices within `reach` of `at` and the
  // edges passing within it; returns how many.
  size_t forget_ball(const Eigen::Vector3d& at, double reach) {
    auto state_touches = [&](const ob::State* s) {
      return gap(pose_of(s).translation(), at) <= reach;
    };
    auto motion_touches = [&](const ob::State* a, const ob::State* b) {
      const Eigen::Vector3d ca = pose_of(a).translation(), cb = pose_of(b).translation();
      const Eigen::Vector3d d = cb - ca;
      const double t =
          d.squaredNorm() > 0 ? std::clamp((at - ca).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
      return gap(ca + t * d, at) <= reach;
    };
    const auto [vertices, edges] = planner->forget_validity(state_touches, motion_touches);
    return vertices + edges;
  }

  // The state validity: the body clear of obstacles and of parked teammates.
  bool valid(const Eigen::Isometry3d& T_world_body) const {
    return !map.collides(T_world_body) && clear_of_parked(T_world_body.translation());
  }
  // --- the roadmap's cached validity, forgotten near changed blocks ---
  std::pair<size_t, size_t> forget_near(const std::vector<tsdf::BlockIndex>& changed) {
    if (changed.empty() || planner->vertex_count() == 0) return {0, 0};
    const double block_m = map.snapshot()->voxel_m() * tsdf::kBlockSide;
    const double r = body.bounding_radius_m();
    std::unordered_set<tsdf::BlockIndex, tsdf::BlockIndexHash> set(changed.begin(), changed.end());
    auto box_touches = [&](const Eigen::Vector3d& lo_m, const Eigen::Vector3d& hi_m) {
      const Eigen::Vector3i lo = (lo_m / block_m).array().floor().cast<int>();
      const Eigen::Vector3i hi = (hi_m / block_m).array().floor().cast<int>();
      const Eigen::Vector3i n = hi - lo + Eigen::Vector3i::Ones();
      if (static_cast<double>(n.x()) * n.y() * n.z() <= static_cast<double>(set.size())) {
        for (int z = lo.z(); z <= hi.z(); ++z)
          for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x)
              if (set.count(tsdf::BlockIndex(x, y, z)) != 0) return true;
        return false;
      }
      for (const tsdf::BlockIndex& b : changed)
        if ((b.array() >= lo.array()).all() && (b.array() <= hi.array()).all()) return true;
      return false;
    };
    const Eigen::Vector3d pad = Eigen::Vector3d::Constant(r);
    auto state_touches = [&](const ob::State* s) {
      const Eigen::Vector3d c = pose_of(s).translation();
      return box_touches(c - pad, c + pad);
    };
    auto motion_touches = [&](const ob::State* a, const ob::State* b) {
      const Eigen::Vector3d ca = pose_of(a).translation(), cb = pose_of(b).translation();
      return box_touches(ca.cwiseMin(cb) - pad, ca.cwiseMax(cb) + pad);
    };
    return planner->forget_validity(state_touches, motion_touches);
  }

  PlanResult fail(PlanStatus status, std::string message, const msg::Waypoint& goal) {
    PlanResult r;
    r.status = status;
    r.message = std::move(message);
    const bool same = last_logged && last_logged->first == status &&
                      last_logged->second.position.x == goal.position.x &&
                      last_logged->second.position.y == goal.position.y &&
                      last_logged->second.position.z == goal.position.z &&
                      last_logged->second.yaw_rad == goal.yaw_rad;
    if (!same) {
      r.first_report = true;
      last_logged = std::make_pair(status, goal);
    }
    return r;
  }

  PlanResult plan(const PlanRequest& q);
  std::optional<PlanResult> check_request(const PlanRequest& q);
  std::optional<PlanResult> search(const PlanRequest& q, const ob::ScopedState<>& start,
                                   const ob::ScopedState<>& goal, double straight,
                                   og::PathGeometric& path, PlanStats& stats, size_t checks0,
                                   Clock::time_point t0);
  PlanResult search_failed(const PlanRequest& q, const ob::PlannerStatus& status,
                           const std::string& error, const PlanStats& stats, size_t checks0,
                           Clock::time_point t0);

  // Guided sampling (guide_path.hpp): poses along the grid path from start to goal, those
  // free of collision, become roadmap milestones.
  void add_guide(const msg::Waypoint& start, const msg::Waypoint& goal, PlanStats& stats) {
    const auto t0 = Clock::now();
    const Eigen::AlignedBox2d box(bounds.min().head<2>(), bounds.max().head<2>());
    const auto& snapshot = map.snapshot();
    if (!guide || guide->map_sequence() != snapshot->sequence() || !guide->bounds().isApprox(box)) {
      GuideConfig g;
      // the body's mid-height layer: its cross-section there holds the disc of the smaller
      // semi-axis (higher and lower, the ellipsoid narrows)
      g.z_lo_m = config.ground_body.safety_center_z_m;
      g.z_hi_m = config.ground_body.safety_center_z_m;
      g.clearance_m = body.safety_radii_m.head<2>().minCoeff();
      g.spacing_m = body.bounding_radius_m();
      g.unknown_is_occupied = config.unknown_is_occupied;
      guide.emplace(*snapshot, box, g);
    }
    const std::vector<GuidePose> poses =
        guide->search({start.position.x, start.position.y}, {goal.position.x, goal.position.y});
    ob::ScopedState<> s(space);
    // a grid cell's centre may sit off the passage's middle by up to half a cell: the pose
    // is nudged sideways (and turned a little) until the body is free
    const double v = snapshot->voxel_m();
    const std::array<double, 5> side{0.0, -0.25 * v, 0.25 * v, -0.5 * v, 0.5 * v};
    const std::array<double, 3> turn{0.0, -0.1, 0.1};
    for (const GuidePose& p : poses) {
      msg::Waypoint w;
      bool free = false;
      for (size_t k = 0; k < side.size() * turn.size() && !free; ++k) {
        const double yaw = p.yaw + turn[k / side.size()];
        const double off = side[k % side.size()];
        w.position = {p.x - off * std::sin(yaw), p.y + off * std::cos(yaw),
                      config.ground_body.safety_center_z_m};
        w.yaw_rad = yaw;
        free = !map.collides(pose_of(w));
      }
      if (!free) continue;
      set_state(s.get(), w);
      planner->add_checked_milestone(s.get());
      ++stats.guide_milestones;
    }
    stats.guide_ms = ms_since(t0);
  }
  RoadmapDistances roadmap_distances(const msg::Waypoint& from,
                                     const std::vector<msg::Waypoint>& targets);

  // Whether `goal` could be planned to (plan()'s goal tests, without messages).
  bool valid_goal(const msg::Waypoint& goal) const {
    if (!finite(goal)) return false;
    if (!ground() && (goal.position.z < config.multirotor_min_altitude_m ||
                      goal.position.z > config.multirotor_max_altitude_m))
      return false;
    if (config.unknown_is_occupied && map.state_at(center_of(goal)) == tsdf::VoxelState::kUnknown)
      return false;
    return valid(pose_of(goal));
  }

  // LazyPRM* takes its optimization objective (the edges' weights) at setup(), which
  // needs a problem definition: solve() does it on the first plan(); roadmap_distances()
  // may come first.
  void ensure_setup(const ob::State* s) {
    if (planner->isSetup()) return;
    auto pdef = std::make_shared<ob::ProblemDefinition>(si);
    pdef->addStartState(s);
    pdef->setGoalState(s, config.goal_tolerance_m);
    pdef->setOptimizationObjective(objective);
    planner->setProblemDefinition(pdef);
    planner->setup();
  }
};

}  // namespace scancrew::motion
