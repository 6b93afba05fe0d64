#pragma once

// The ATSP engine behind solve_closed_atsp and solve_max_open_path (atsp.hpp): an iterated
// local search on a finite cost matrix. Internal to the library; the public entry points
// validate the input, map forbidden arcs to a finite penalty and handle n <= 3.
//
// 1. Construction: greedy edge (arcs by increasing cost, ties by index; an arc is taken
//    when its tail has no successor, its head no predecessor and it closes no subtour).
// 2. Local search: the sequential 3-opt move that keeps every segment's orientation
//    ("or-3opt", the only such reconnection of three removed arcs): the tour
//    x x'..z y..w w' .. becomes x y..w x'..z w' .., i.e. two adjacent segments are
//    exchanged; Or-opt is the case of a short segment. Moves are searched from a base node
//    x over candidate lists (the k cheapest out-arcs and in-arcs of every node) under the
//    positive-gain criterion, first improvement, with don't-look bits kept as a FIFO queue
//    of active nodes (Bentley 1992; Johnson & McGeoch 2002 for the asymmetric case).
// 3. Iterated local search: a segment-local double bridge (segments B C D of 1..50 nodes
//    after a random node become D C B; four arcs change, no orientation changes, so the
//    kick is valid for the ATSP and no single 3-opt move undoes it) followed by the local
//    search from the eight nodes it touched. The result replaces the current tour when it
//    is no worse, and otherwise the kick is undone, except that after every 10 kicks
//    without a new best tour the worse result is kept (a random-walk step out of the
//    basin; pure descent stalls on ftv170). The best tour seen is returned (Martin, Otto &
//    Felten 1991; Lourenço, Martin & Stützle 2003).
//
// Allocation: everything is sized in the constructor; a kick and its local search
// allocate nothing. Not thread safe: one engine per thread.

#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

namespace scancrew::tsga::detail {

// splitmix64: the same sequence on every platform (std distributions are not).
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t next();
  // uniform in [0, bound), bound >= 1 (Lemire's multiply-shift; the bias is below 2^-32
  // for the bounds used here)
  int below(int bound);

 private:
  uint64_t state_;
};

struct IlsParams {
  int max_iterations = 1000;
  double time_limit_ms = 0.0;  // 0 = none
  uint64_t seed = 1;
  int neighbours = 10;
};

struct IlsOutcome {
  std::vector<int> tour;  // starts at node 0
  double cost = 0.0;
  int iterations = 0;
  bool time_limited = false;
};

// costs: n x n, row-major, finite off the diagonal (the diagonal is not read); n >= 4.
IlsOutcome iterated_local_search(std::span<const double> costs, int n, const IlsParams& params);

class IlsEngine {
 public:
  IlsEngine(std::span<const double> costs, int n, int neighbours);

  void construct_greedy();
  // drains the queue of active nodes; returns the moves applied
  int64_t local_search();
  void double_bridge(SplitMix64& rng);
  void activate_all();

  double cost() const;
  const std::vector<int>& tour() const { return tour_; }
  void set_tour(const std::vector<int>& tour);

 private:
  double c(int from, int to) const {
    return costs_[static_cast<size_t>(from) * static_cast<size_t>(n_) + static_cast<size_t>(to)];
  }
  int at(int position) const { return tour_[static_cast<size_t>(wrap(position))]; }
  int wrap(int position) const { return position >= n_ ? position - n_ : position; }
  int pos(int node) const { return pos_[static_cast<size_t>(node)]; }
  int succ(int node) const { return at(pos(node) + 1); }
  int pred(int node) const { return at(pos(node) + n_ - 1); }
  // position of node counted from base_position, in [0, n)
  int rel(int node, int base_position) const {
    const int r = pos(node) - base_position;
    return r < 0 ? r + n_ : r;
  }
  std::span<const int> out_neighbours(int node) const;
  std::span<const int> in_neighbours(int node) const;

  bool improve_from(int x);
  void apply_or3opt(int x, int y, int w);
  void swap_adjacent_blocks(int start_position, int len_a, int len_b);
  void push(int node);

  std::span<const double> costs_;
  int n_;
  int k_;
  double eps_;
  std::vector<int> out_nb_;  // n x k: cheapest out-arcs of each node
  std::vector<int> in_nb_;   // n x k: cheapest in-arcs of each node
  std::vector<int> tour_;
  std::vector<int> pos_;
  std::vector<int> queue_;  // ring buffer of active nodes, each at most once
  std::vector<char> queued_;
  size_t queue_head_ = 0;
  size_t queue_size_ = 0;
  std::vector<int> scratch_;
};

}  // namespace scancrew::tsga::detail
