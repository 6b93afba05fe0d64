#include "core/ise/clusters.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace scancrew::ise {

namespace {

struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the smaller index is the root
  }
};

struct Cell {
  uint32_t types;
  int x, y, z;
  bool operator==(const Cell&) const = default;
};
struct CellHash {
  size_t operator()(const Cell& c) const {
    return static_cast<size_t>(c.x) * 73856093u ^ static_cast<size_t>(c.y) * 19349669u ^
           static_cast<size_t>(c.z) * 83492791u ^ static_cast<size_t>(c.types) * 2654435761u;
  }
};

// Viewpoints hashed by (types, cell of side `side`).
class Grid {
 public:
  Grid(const std::vector<Viewpoint>& vps, double side) : vps_(vps), side_(side) {
    for (uint32_t i = 0; i < vps.size(); ++i) cells_[cell(vps[i])].push_back(i);
  }
  // Calls f(j) for every viewpoint j ≠ i of i's types within `radius` (radius ≤ k·side).
  template <class F>
  void near(uint32_t i, double radius, F&& f) const {
    const Cell c = cell(vps_[i]);
    const int k = static_cast<int>(std::ceil(radius / side_));
    for (int dz = -k; dz <= k; ++dz)
      for (int dy = -k; dy <= k; ++dy)
        for (int dx = -k; dx <= k; ++dx) {
          const auto it = cells_.find({c.types, c.x + dx, c.y + dy, c.z + dz});
          if (it == cells_.end()) continue;
          for (uint32_t j : it->second) {
            if (j == i) continue;
            const double d = (vps_[j].position - vps_[i].position).norm();
            if (d < radius) f(j, d);
          }
        }
  }

 private:
  Cell cell(const Viewpoint& v) const {
    return {v.types, static_cast<int>(std::floor(v.position.x() / side_)),
            static_cast<int>(std::floor(v.position.y() / side_)),
            static_cast<int>(std::floor(v.position.z() / side_))};
  }
  const std::vector<Viewpoint>& vps_;
  double side_;
  std::unordered_map<Cell, std::vector<uint32_t>, CellHash> cells_;
};

}  // namespace

std::vector<Cluster> cluster_viewpoints(const std::vector<Viewpoint>& viewpoints, double d_v_m,
                                        double d_v_max_m) {
  const auto n = static_cast<uint32_t>(viewpoints.size());
  UnionFind uf(n);
  const Grid grid(viewpoints, d_v_m);
  std::vector<bool> has_neighbour(n, false);
  for (uint32_t i = 0; i < n; ++i)
    grid.near(i, d_v_m, [&](uint32_t j, double) {
      has_neighbour[i] = true;
      uf.join(i, j);
    });
  // isolated viewpoints: d_v grows up to d_v^max, i.e. the nearest one within d_v^max
  if (d_v_max_m > d_v_m) {
    std::vector<std::pair<uint32_t, uint32_t>> joins;
    for (uint32_t i = 0; i < n; ++i) {
      if (has_neighbour[i]) continue;
      uint32_t best = n;
      double best_d = d_v_max_m;
      grid.near(i, d_v_max_m, [&](uint32_t j, double d) {
        if (d < best_d || (d == best_d && j < best)) {
          best_d = d;
          best = j;
        }
      });
      if (best < n) joins.emplace_back(i, best);
    }
    for (const auto& [a, b] : joins) uf.join(a, b);
  }
  std::vector<Cluster> clusters;
  std::unordered_map<uint32_t, uint32_t> cluster_of_root;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t root = uf.find(i);
    auto [it, fresh] = cluster_of_root.try_emplace(root, static_cast<uint32_t>(clusters.size()));
    if (fresh) {
      Cluster c;
      c.id = it->second;
      c.types = viewpoints[i].types;
      clusters.push_back(c);
    }
    Cluster& c = clusters[it->second];
    c.viewpoints.push_back(i);
    c.centroid += viewpoints[i].position;
  }
  for (Cluster& c : clusters) c.centroid /= static_cast<double>(c.viewpoints.size());
  return clusters;
}

void compute_gains(std::vector<Cluster>& clusters, const std::vector<Viewpoint>& viewpoints,
                   size_t total_ises) {
  for (Cluster& c : clusters) {
    c.seen.clear();
    for (uint32_t v : c.viewpoints)
      c.seen.insert(c.seen.end(), viewpoints[v].seen.begin(), viewpoints[v].seen.end());
    std::sort(c.seen.begin(), c.seen.end());
    c.seen.erase(std::unique(c.seen.begin(), c.seen.end()), c.seen.end());
    c.gain = total_ises == 0 ? 0.0
                             : static_cast<double>(c.seen.size()) / static_cast<double>(total_ises);
  }
}

}  // namespace scancrew::ise
