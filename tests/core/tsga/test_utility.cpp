// The utilities of eq. 2.3: values, unreachable clusters as forbidden arcs, and refused
// input (duplicate ids, NaN or negative gains and lengths, mismatched sizes).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/tsga/utility.hpp"

namespace scancrew::tsga {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Graph {
  std::vector<uint64_t> ids{7, 3, 11};
  std::vector<double> gains{0.0, 0.5, 0.25};
  CostMatrix inter{3, 2.0};
  CostMatrix intra{3, 1.0};
};

TEST(Utility, FollowsEquationTwoThree) {
  Graph g;
  g.inter(0, 2) = 10.0;
  auto f = utility_matrix(g.ids, g.gains, g.inter, g.intra, {0.1, 0.2});
  ASSERT_TRUE(f) << f.error();
  EXPECT_DOUBLE_EQ((*f)(0, 1), 0.5 * std::exp(-0.1 * 2.0 - 0.2 * 1.0));
  EXPECT_DOUBLE_EQ((*f)(0, 2), 0.25 * std::exp(-0.1 * 10.0 - 0.2 * 1.0));
  EXPECT_DOUBLE_EQ((*f)(2, 0), 0.0);  // the start's gain
}

TEST(Utility, UnreachableClusterIsAForbiddenArc) {
  Graph g;
  g.inter(1, 2) = kInf;
  auto f = utility_matrix(g.ids, g.gains, g.inter, g.intra);
  ASSERT_TRUE(f);
  EXPECT_EQ((*f)(1, 2), -kInf);
  auto path = solve_max_open_path(*f, 0);
  ASSERT_TRUE(path);
  EXPECT_EQ(path->nodes, (std::vector<int>{0, 2, 1}));
  EXPECT_TRUE(std::isfinite(path->utility));
}

TEST(Utility, RefusesDuplicateIds) {
  Graph g;
  g.ids = {7, 3, 7};
  auto f = utility_matrix(g.ids, g.gains, g.inter, g.intra);
  ASSERT_FALSE(f);
  EXPECT_EQ(f.error(), "utility_matrix: duplicate cluster id 7 (nodes 0 and 2)");
}

TEST(Utility, RefusesNaNOrNegativeGainsAndLengths) {
  Graph g;
  g.gains[1] = kNaN;
  auto nan_gain = utility_matrix(g.ids, g.gains, g.inter, g.intra);
  ASSERT_FALSE(nan_gain);
  EXPECT_EQ(nan_gain.error(), "utility_matrix: gain of cluster 3 is NaN; allowed: finite, >= 0");
  g.gains[1] = -1.0;
  EXPECT_FALSE(utility_matrix(g.ids, g.gains, g.inter, g.intra));
  g = Graph{};
  g.inter(2, 1) = kNaN;
  auto nan_length = utility_matrix(g.ids, g.gains, g.inter, g.intra);
  ASSERT_FALSE(nan_length);
  EXPECT_EQ(nan_length.error(),
            "utility_matrix: inter-cluster length (2, 1) is NaN; allowed: >= 0 or +infinity "
            "(unreachable)");
  g = Graph{};
  g.intra(0, 1) = -3.0;
  EXPECT_FALSE(utility_matrix(g.ids, g.gains, g.inter, g.intra));
  g = Graph{};
  EXPECT_FALSE(utility_matrix(g.ids, g.gains, g.inter, g.intra, {kNaN, 0.1}));
}

TEST(Utility, RefusesMismatchedSizesAndAcceptsAnEmptyGraph) {
  Graph g;
  g.gains.pop_back();
  auto f = utility_matrix(g.ids, g.gains, g.inter, g.intra);
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().find("all must agree"), std::string::npos);
  auto empty = utility_matrix({}, {}, CostMatrix(), CostMatrix());
  ASSERT_TRUE(empty);
  EXPECT_EQ(empty->size(), 0u);
}

}  // namespace
}  // namespace scancrew::tsga
