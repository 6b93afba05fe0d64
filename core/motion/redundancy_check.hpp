#pragma once

// RedundancyCheck (thesis 4.5.2 item 6, Algorithm 6 lines 5-8, Fig. 4.4): with distributed
// maps, dist-TSGA may give the same cluster to several robots. Each robot broadcasts its
// tour and progress; for a cluster in several tours, the robot with the fewest "steps"
// (paths p^i still to follow before reaching it) keeps it (Situation 1); on equal steps the
// one closer to it does (Situation 2); the others keep following their tours up to the
// cluster just before the contested one, and there wait for a new plan (redundancy = True).
//
// Choices where the thesis is silent (docs/traffic_policy.md):
// - clusters are matched by their goal configurations (within same_goal_distance_m), since
//   cluster ids of different robots' maps need not agree; matching ids can be used too;
// - steps: the next goal is 1 step away, the one after 2, ...; a cluster a teammate has
//   already reached counts 0 steps (it is taken);
// - distance: along the tour (the robot's position, then its goals in order, straight
//   lines), which is the Euclidean distance when the cluster is the next goal;
// - a tie in steps and distance goes to the lower robot id.
// Deterministic; pure function, any thread; allocates the result's list.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace scancrew::motion {

struct TourStop {
  uint32_t cluster_id = 0;
  Eigen::Vector3d goal = Eigen::Vector3d::Zero();  // the configuration to reach (viewpoint)
};

// A robot's tour P^i and its progress along it.
struct TourProgress {
  uint32_t robot_id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  std::vector<TourStop> tour;  // the whole sequence, in order
  size_t next = 0;             // index of the cluster it is heading to (tour.size(): done)
};

struct RedundancyConfig {
  // two tour stops are the same cluster when their goals are this close (the ISE
  // extractor's viewpoint merge distance, ise_config.hpp)
  double same_goal_distance_m = 0.5;
  // also match stops with equal cluster ids (a shared map: centralized plans)
  bool match_cluster_ids = false;
  // compare goals in the plane (ground robots)
  bool planar = false;

  std::string validate() const;
};

// One of this robot's remaining clusters that a teammate also has.
struct Contest {
  size_t tour_index = 0;  // in this robot's tour
  uint32_t cluster_id = 0;
  uint32_t winner_id = 0;
  bool won = false;  // this robot keeps the cluster
  size_t steps = 0;  // this robot's steps to it
  double distance_m = 0;
  size_t winner_steps = 0;
  double winner_distance_m = 0;
};

struct RedundancyResult {
  // RedundancyCheck's output: the next cluster belongs to a teammate; wait for a new plan
  bool redundancy = false;
  // the first lost cluster: the robot follows its tour up to the one before it
  std::optional<size_t> stop_before_index;
  std::vector<Contest> contests;  // in tour order
};

// RedundancyCheck(q_i, q_k, P^i, P^k). Teammates with this robot's id are ignored.
RedundancyResult redundancy_check(const TourProgress& self, std::span<const TourProgress> teammates,
                                  const RedundancyConfig& config);

}  // namespace scancrew::motion
