#include "core/motion/redundancy_check.hpp"

namespace scancrew::motion {

std::string RedundancyConfig::validate() const {
  if (!(same_goal_distance_m >= 0)) return "same_goal_distance_m must be >= 0";
  return {};
}

namespace {

struct Claim {
  uint32_t robot = 0;
  size_t steps = 0;
  double distance_m = 0;
};

// lexicographic (steps, distance, id): the smaller one has priority
bool before(const Claim& a, const Claim& b) {
  if (a.steps != b.steps) return a.steps < b.steps;
  if (a.distance_m != b.distance_m) return a.distance_m < b.distance_m;
  return a.robot < b.robot;
}

double gap(const Eigen::Vector3d& a, const Eigen::Vector3d& b, bool planar) {
  const Eigen::Vector3d d = a - b;
  return planar ? d.head<2>().norm() : d.norm();
}

// The robot's claim on its tour stop `index`: steps and distance along the tour.
Claim claim(const TourProgress& p, size_t index, bool planar) {
  Claim c;
  c.robot = p.robot_id;
  if (index < p.next) return c;  // already reached: taken
  c.steps = index - p.next + 1;
  Eigen::Vector3d at = p.position;
  for (size_t j = p.next; j <= index; ++j) {
    c.distance_m += gap(at, p.tour[j].goal, planar);
    at = p.tour[j].goal;
  }
  return c;
}

bool same_cluster(const TourStop& a, const TourStop& b, const RedundancyConfig& config) {
  if (config.match_cluster_ids && a.cluster_id == b.cluster_id) return true;
  return gap(a.goal, b.goal, config.planar) <= config.same_goal_distance_m;
}

bool finite(const TourProgress& p) {
  if (!p.position.allFinite()) return false;
  for (const TourStop& s : p.tour)
    if (!s.goal.allFinite()) return false;
  return true;
}

}  // namespace

RedundancyResult redundancy_check(const TourProgress& self, std::span<const TourProgress> teammates,
                                  const RedundancyConfig& config) {
  RedundancyResult r;
  if (!finite(self)) return r;
  for (size_t i = self.next; i < self.tour.size(); ++i) {
    const Claim mine = claim(self, i, config.planar);
    Claim best = mine;
    bool contested = false;
    for (const TourProgress& k : teammates) {
      if (k.robot_id == self.robot_id || !finite(k)) continue;
      // the teammate's best claim on this cluster (a tour may hold it twice)
      bool has = false;
      Claim theirs;
      for (size_t j = 0; j < k.tour.size(); ++j) {
        if (!same_cluster(self.tour[i], k.tour[j], config)) continue;
        const Claim c = claim(k, j, config.planar);
        if (!has || before(c, theirs)) theirs = c;
        has = true;
      }
      if (!has) continue;
      contested = true;
      if (before(theirs, best)) best = theirs;
    }
    if (!contested) continue;
    Contest c;
    c.tour_index = i;
    c.cluster_id = self.tour[i].cluster_id;
    c.winner_id = best.robot;
    c.won = best.robot == self.robot_id;
    c.steps = mine.steps;
    c.distance_m = mine.distance_m;
    c.winner_steps = best.steps;
    c.winner_distance_m = best.distance_m;
    if (!c.won && !r.stop_before_index) r.stop_before_index = i;
    r.contests.push_back(c);
  }
  r.redundancy = r.stop_before_index && *r.stop_before_index == self.next;
  return r;
}

}  // namespace scancrew::motion
