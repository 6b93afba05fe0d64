#include "core/tsga/ils_engine.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <queue>
#include <utility>

namespace scancrew::tsga::detail {

namespace {

// longest segment of a double-bridge kick: local kicks keep the local search short
constexpr int kMaxKickSegment = 50;
// kicks without a new best tour after which a worse tour is kept anyway (measured on the
// TSPLIB instances: 5 to 30 all work; pure descent stalls on ftv170 at +0.33 %)
constexpr int kKicksPerWalk = 10;

size_t idx(int i) {
  return static_cast<size_t>(i);
}

// union-find over nodes for the greedy construction's subtour test
int find_root(std::vector<int>& parent, int v) {
  while (parent[idx(v)] != v) {
    parent[idx(v)] = parent[idx(parent[idx(v)])];
    v = parent[idx(v)];
  }
  return v;
}

}  // namespace

uint64_t SplitMix64::next() {
  state_ += 0x9e3779b97f4a7c15ULL;
  uint64_t z = state_;
  z = (z ^ (z >> 30U)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27U)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31U);
}

int SplitMix64::below(int bound) {
  const uint64_t r = next() >> 32U;
  return static_cast<int>((r * static_cast<uint64_t>(bound)) >> 32U);
}

IlsEngine::IlsEngine(std::span<const double> costs, int n, int neighbours)
    : costs_(costs), n_(n), k_(std::clamp(neighbours, 1, n - 1)), eps_(0.0) {
  const size_t nn = idx(n);
  const size_t k = idx(k_);
  double scale = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j) scale = std::max(scale, std::abs(c(i, j)));
  // gains below this are rounding noise: a move must gain more to be applied
  eps_ = 1e-12 * std::max(scale, 1e-300);

  // candidate lists: the k cheapest arcs out of and into every node, ties by index
  out_nb_.resize(nn * k);
  in_nb_.resize(nn * k);
  std::vector<int> others(nn - 1);
  for (int v = 0; v < n; ++v) {
    int m = 0;
    for (int u = 0; u < n; ++u)
      if (u != v) others[idx(m++)] = u;
    auto take = [&](std::vector<int>& out, auto value) {
      std::partial_sort(others.begin(), others.begin() + k_, others.end(), [&](int a, int b) {
        const double va = value(a);
        const double vb = value(b);
        return va < vb || (va == vb && a < b);
      });
      std::copy_n(others.begin(), k, out.begin() + static_cast<std::ptrdiff_t>(idx(v) * k));
    };
    take(out_nb_, [&](int u) { return c(v, u); });
    take(in_nb_, [&](int u) { return c(u, v); });
  }

  tour_.resize(nn);
  std::iota(tour_.begin(), tour_.end(), 0);
  pos_ = tour_;
  queue_.resize(nn);
  queued_.assign(nn, 0);
  scratch_.resize(nn);
}

std::span<const int> IlsEngine::out_neighbours(int node) const {
  return {out_nb_.data() + idx(node) * idx(k_), idx(k_)};
}

std::span<const int> IlsEngine::in_neighbours(int node) const {
  return {in_nb_.data() + idx(node) * idx(k_), idx(k_)};
}

void IlsEngine::construct_greedy() {
  // Greedy edge, lazily: the arcs are taken in (cost, index) order, as a full sort would
  // give them, but each node's out-arcs are read in (cost, head) order from its candidate
  // list, and only a node that has used those up gets its whole row sorted. A heap holds
  // one arc per node that still has no successor: its cheapest arc not yet refused. An arc
  // that becomes unusable stays so, so the arc popped first among the usable ones is the
  // cheapest usable arc of all. (Sorting all n² arcs was the TSGA planner's largest cost on
  // the powerplant's clusters of hundreds of viewpoints; docs/tsga.md.)
  const size_t nn = idx(n_);
  const size_t k = idx(k_);
  std::vector<std::vector<int>> row(nn);  // a node's heads in (cost, head) order, on demand
  const auto head_at = [&](int i, int rank) {
    if (rank < k_) return out_nb_[idx(i) * k + idx(rank)];
    std::vector<int>& r = row[idx(i)];
    if (r.empty()) {
      for (int j = 0; j < n_; ++j)
        if (j != i) r.push_back(j);
      std::sort(r.begin(), r.end(), [&](int a, int b) {
        const double ca = c(i, a);
        const double cb = c(i, b);
        return ca < cb || (ca == cb && a < b);
      });
    }
    return r[idx(rank)];
  };
  std::vector<int> rank(nn, 0);
  using Arc = std::pair<double, int>;  // (cost, i * n + j): the order of a full sort
  std::priority_queue<Arc, std::vector<Arc>, std::greater<>> heap;
  const auto push_next = [&](int i) {
    if (rank[idx(i)] >= n_ - 1) return;
    const int j = head_at(i, rank[idx(i)]);
    heap.emplace(c(i, j), i * n_ + j);
  };
  for (int i = 0; i < n_; ++i) push_next(i);
  std::vector<int> next(nn, -1);
  std::vector<int> prev(nn, -1);
  std::vector<int> parent(nn);
  std::iota(parent.begin(), parent.end(), 0);
  int added = 0;
  while (added < n_ - 1 && !heap.empty()) {
    const int a = heap.top().second;
    heap.pop();
    const int i = a / n_;
    const int j = a % n_;
    // i has no successor (a node leaves the heap when it gets one)
    if (prev[idx(j)] >= 0 || find_root(parent, i) == find_root(parent, j)) {
      ++rank[idx(i)];  // refused for good: j has a predecessor, or i and j share a path
      push_next(i);
      continue;
    }
    next[idx(i)] = j;
    prev[idx(j)] = i;
    parent[idx(find_root(parent, i))] = find_root(parent, j);
    ++added;
  }
  // one path is left: walk it from its head
  int head = 0;
  while (prev[idx(head)] >= 0) head = prev[idx(head)];
  for (int p = 0, v = head; p < n_; ++p, v = next[idx(v)]) {
    tour_[idx(p)] = v;
    pos_[idx(v)] = p;
  }
}

void IlsEngine::set_tour(const std::vector<int>& tour) {
  tour_ = tour;
  for (int p = 0; p < n_; ++p) pos_[idx(tour_[idx(p)])] = p;
}

double IlsEngine::cost() const {
  double sum = 0.0;
  for (int p = 0; p < n_; ++p) sum += c(tour_[idx(p)], at(p + 1));
  return sum;
}

void IlsEngine::push(int node) {
  if (queued_[idx(node)] != 0) return;
  queued_[idx(node)] = 1;
  queue_[(queue_head_ + queue_size_) % idx(n_)] = node;
  ++queue_size_;
}

void IlsEngine::activate_all() {
  for (int p = 0; p < n_; ++p) push(tour_[idx(p)]);
}

int64_t IlsEngine::local_search() {
  // a generous cap: every applied move gains more than eps_, so this is never reached on
  // sane input; it only bounds the work if rounding ever made two moves undo each other
  const int64_t max_moves = 1000 * static_cast<int64_t>(n_) * n_;
  int64_t moves = 0;
  while (queue_size_ > 0) {
    const int x = queue_[queue_head_];
    queue_head_ = (queue_head_ + 1) % idx(n_);
    --queue_size_;
    queued_[idx(x)] = 0;
    if (moves < max_moves && improve_from(x)) {
      ++moves;
      push(x);
    }
  }
  return moves;
}

// The or-3opt move with base x: remove (x, x'), (z, y), (w, w'); add (x, y), (w, x'),
// (z, w'), where y follows x' (y != x'), z = pred(y) and w is y or after it. Two ways to
// pick the second new arc: w among the cheapest predecessors of x' (A), or w' among the
// cheapest successors of z (B). Rotating the base over the three tails of the removed
// arcs, B alone meets every improving move (a cyclic sum that is positive has a rotation
// with positive partial sums); A adds moves whose arc (w, x') is cheap from x''s side.
bool IlsEngine::improve_from(int x) {
  const int base = pos(x);
  const int x1 = succ(x);
  const double g0 = c(x, x1);
  for (int y : out_neighbours(x)) {
    const double g1 = g0 - c(x, y);
    if (g1 <= 0.0) break;
    const int ry = rel(y, base);
    if (ry < 2) continue;  // y is x' (or x)
    const int z = at(base + ry - 1);
    const double g1z = g1 + c(z, y);
    // (A) w among the in-candidates of x'
    for (int w : in_neighbours(x1)) {
      const double g2 = g1z - c(w, x1);
      if (g2 <= 0.0) break;
      const int rw = rel(w, base);
      if (rw < ry) continue;
      const int w1 = at(base + rw + 1);
      if (g2 + c(w, w1) - c(z, w1) > eps_) {
        apply_or3opt(x, y, w);
        return true;
      }
    }
    // (B) w' among the out-candidates of z
    for (int w1 : out_neighbours(z)) {
      const double g2 = g1z - c(z, w1);
      if (g2 <= 0.0) break;
      int rw1 = rel(w1, base);
      if (rw1 == 0) rw1 = n_;  // w' = x: w is the last node before x
      if (rw1 <= ry) continue;
      const int w = at(base + rw1 - 1);
      if (g2 + c(w, w1) - c(w, x1) > eps_) {
        apply_or3opt(x, y, w);
        return true;
      }
    }
  }
  return false;
}

void IlsEngine::apply_or3opt(int x, int y, int w) {
  const int base = pos(x);
  const int ry = rel(y, base);
  const int rw = rel(w, base);
  const int x1 = at(base + 1);
  const int z = at(base + ry - 1);
  const int w1 = at(base + rw + 1);
  // segments after x: S1 = x'..z, S2 = y..w, S3 = w'..x; exchanging any two adjacent ones
  // gives the same cyclic tour x y..w x'..z w'..: rewrite the shortest pair
  const int l1 = ry - 1;
  const int l2 = rw - ry + 1;
  const int l3 = n_ - l1 - l2;
  if (l1 + l2 <= l2 + l3 && l1 + l2 <= l3 + l1) {
    swap_adjacent_blocks(wrap(base + 1), l1, l2);
  } else if (l2 + l3 <= l3 + l1) {
    swap_adjacent_blocks(wrap(base + ry), l2, l3);
  } else {
    swap_adjacent_blocks(wrap(base + rw + 1), l3, l1);
  }
  for (int v : {x, x1, z, y, w, w1}) push(v);
}

// The blocks A = [start, start + len_a) and B = [start + len_a, start + len_a + len_b),
// cyclic positions, become B A.
void IlsEngine::swap_adjacent_blocks(int start_position, int len_a, int len_b) {
  const int len = len_a + len_b;
  for (int i = 0; i < len_b; ++i) scratch_[idx(i)] = at(start_position + len_a + i);
  for (int i = 0; i < len_a; ++i) scratch_[idx(len_b + i)] = at(start_position + i);
  for (int i = 0; i < len; ++i) {
    const int p = wrap(start_position + i);
    tour_[idx(p)] = scratch_[idx(i)];
    pos_[idx(scratch_[idx(i)])] = p;
  }
}

void IlsEngine::double_bridge(SplitMix64& rng) {
  const int max_len = std::min(kMaxKickSegment, (n_ - 1) / 3);
  const int p0 = rng.below(n_);
  const int lb = 1 + rng.below(max_len);
  const int lc = 1 + rng.below(max_len);
  const int ld = 1 + rng.below(max_len);
  // A | B C D | A  ->  A | D C B | A
  const int start = wrap(p0 + 1);
  int o = 0;
  for (int i = 0; i < ld; ++i) scratch_[idx(o++)] = at(start + lb + lc + i);
  for (int i = 0; i < lc; ++i) scratch_[idx(o++)] = at(start + lb + i);
  for (int i = 0; i < lb; ++i) scratch_[idx(o++)] = at(start + i);
  const int len = lb + lc + ld;
  for (int i = 0; i < len; ++i) {
    const int p = wrap(start + i);
    tour_[idx(p)] = scratch_[idx(i)];
    pos_[idx(scratch_[idx(i)])] = p;
  }
  // the ends of the four new arcs
  for (int p :
       {p0, p0 + 1, p0 + ld, p0 + ld + 1, p0 + ld + lc, p0 + ld + lc + 1, p0 + len, p0 + len + 1})
    push(at(p));
}

IlsOutcome iterated_local_search(std::span<const double> costs, int n, const IlsParams& params) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  IlsEngine engine(costs, n, params.neighbours);
  SplitMix64 rng(params.seed);
  engine.construct_greedy();
  engine.activate_all();
  engine.local_search();

  IlsOutcome out;
  out.tour = engine.tour();
  out.cost = engine.cost();
  std::vector<int> current = out.tour;
  double current_cost = out.cost;
  int since_best = 0;
  for (int it = 0; it < params.max_iterations; ++it) {
    if (params.time_limit_ms > 0.0 && (it & 15) == 0) {
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      if (ms > params.time_limit_ms) {
        out.time_limited = true;
        break;
      }
    }
    engine.double_bridge(rng);
    engine.local_search();
    ++out.iterations;
    const double cost = engine.cost();
    if (cost < out.cost) {
      out.cost = cost;
      out.tour = engine.tour();
      since_best = 0;
    } else {
      ++since_best;
    }
    // no worse than the current tour: keep it; worse: undo the kick, except every
    // kKicksPerWalk kicks without a new best, when the walk leaves the basin
    if (cost <= current_cost || since_best % kKicksPerWalk == 0) {
      current_cost = cost;
      current = engine.tour();
    } else {
      engine.set_tour(current);
    }
  }
  // rotate to start at node 0
  const auto zero = std::find(out.tour.begin(), out.tour.end(), 0);
  std::rotate(out.tour.begin(), zero, out.tour.end());
  return out;
}

}  // namespace scancrew::tsga::detail
