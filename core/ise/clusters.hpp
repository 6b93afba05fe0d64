#pragma once

// Clusters of viewpoints (thesis 2.4.3): a viewpoint belongs to a cluster when some member
// is within d_v of it (the clusters are the connected components of the "closer than d_v"
// graph); a viewpoint with no neighbour within d_v joins the cluster of its nearest
// viewpoint if that one is within d_v^max (d_v "increased up to d_v^max"), else stays alone.
// Only viewpoints feasible for the same robot types are clustered together, so each
// cluster says which robot types can reach it. Distances are straight-line here; the
// low-level planner's roadmap distance is a later step's option.
//
// Deterministic: the clusters and their members follow the input order.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/ise/viewpoints.hpp"

namespace scancrew::ise {

struct Cluster {
  uint32_t id = 0;                   // its index in the cluster list
  uint32_t types = 0;                // robot types that can reach it (robot::kind_bit()s)
  std::vector<uint32_t> viewpoints;  // indices into the viewpoint list
  std::vector<uint32_t> seen;        // C_U: ISEs seen from its viewpoints, sorted
  double gain = 0;                   // g(U) = |C_U| / |C|
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
};

std::vector<Cluster> cluster_viewpoints(const std::vector<Viewpoint>& viewpoints, double d_v_m,
                                        double d_v_max_m);

// Fills seen and gain from the viewpoints' seen sets; total_ises = |C|.
void compute_gains(std::vector<Cluster>& clusters, const std::vector<Viewpoint>& viewpoints,
                   size_t total_ises);

}  // namespace scancrew::ise
