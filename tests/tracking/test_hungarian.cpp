#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

#include "tracking/sort/hungarian.h"

namespace adugs::tracking {
namespace {

double totalCost(const Eigen::MatrixXd& c, const std::vector<int>& col_of_row) {
  double sum = 0;
  for (int r = 0; r < static_cast<int>(col_of_row.size()); ++r)
    if (col_of_row[r] >= 0) sum += c(r, col_of_row[r]);
  return sum;
}

// Exhaustive minimum over all injective maps of the smaller side into the larger one.
double bruteForceMinimum(const Eigen::MatrixXd& c) {
  const bool rows_small = c.rows() <= c.cols();
  const int small = static_cast<int>(rows_small ? c.rows() : c.cols());
  const int large = static_cast<int>(rows_small ? c.cols() : c.rows());
  std::vector<int> perm(large);
  std::iota(perm.begin(), perm.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    double sum = 0;
    for (int k = 0; k < small; ++k) sum += rows_small ? c(k, perm[k]) : c(perm[k], k);
    best = std::min(best, sum);
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best;
}

TEST(Hungarian, HandWorkedThreeByThree) {
  // All six permutations by hand: (0,1,2) 4+5+2 = 11, (0,2,1) 4+8+6 = 18, (1,0,2) 1+2+2 = 5,
  // (1,2,0) 1+8+1 = 10, (2,0,1) 3+2+6 = 11, (2,1,0) 3+5+1 = 9. Greedy picking of the two
  // global minima c(0,1) = c(2,0) = 1 would force c(1,2) = 8 (total 10).
  Eigen::MatrixXd c(3, 3);
  c << 4, 1, 3, 2, 5, 8, 1, 6, 2;
  const std::vector<int> a = solveAssignment(c);
  EXPECT_EQ(a, (std::vector<int>{1, 0, 2}));
  EXPECT_DOUBLE_EQ(totalCost(c, a), 5.0);
}

TEST(Hungarian, RectangularBothWays) {
  Eigen::MatrixXd wide(2, 3);
  wide << 5, 1, 9, 1, 2, 9;
  EXPECT_EQ(solveAssignment(wide), (std::vector<int>{1, 0}));
  const std::vector<int> tall = solveAssignment(wide.transpose());  // 3 rows, 2 columns
  EXPECT_EQ(tall, (std::vector<int>{1, 0, -1}));
}

TEST(Hungarian, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 60; ++trial) {
    const int rows = 1 + trial % 6, cols = 1 + (trial / 6) % 7;
    Eigen::MatrixXd c(rows, cols);
    for (int r = 0; r < rows; ++r)
      for (int k = 0; k < cols; ++k) c(r, k) = std::round(u(rng) * 20) / 4;  // ties happen
    const std::vector<int> a = solveAssignment(c);
    ASSERT_EQ(static_cast<int>(a.size()), rows);
    std::vector<int> used;
    for (int col : a)
      if (col >= 0) used.push_back(col);
    std::sort(used.begin(), used.end());
    EXPECT_EQ(std::adjacent_find(used.begin(), used.end()), used.end()) << "column used twice";
    EXPECT_EQ(static_cast<int>(used.size()), std::min(rows, cols));
    EXPECT_NEAR(totalCost(c, a), bruteForceMinimum(c), 1e-12) << rows << "x" << cols;
  }
}

TEST(Hungarian, EmptyAndInvalid) {
  EXPECT_TRUE(solveAssignment(Eigen::MatrixXd(0, 3)).empty());
  EXPECT_EQ(solveAssignment(Eigen::MatrixXd(2, 0)), (std::vector<int>{-1, -1}));
  Eigen::MatrixXd bad = Eigen::MatrixXd::Zero(2, 2);
  bad(1, 0) = std::nan("");
  EXPECT_THROW(solveAssignment(bad), std::invalid_argument);
}

}  // namespace
}  // namespace adugs::tracking
