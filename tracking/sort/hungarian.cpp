#include "tracking/sort/hungarian.h"

#include <limits>
#include <stdexcept>

namespace adugs::tracking {
namespace {

// Shortest augmenting paths with row/column potentials u, v (the e-maxx formulation), for
// n <= m. Indices are 1-based inside; column 0 is the virtual start.
std::vector<int> assignRowsToColumns(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows()), m = static_cast<int>(a.cols());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> row_of_col(m + 1, 0), way(m + 1, 0);
  for (int i = 1; i <= n; ++i) {
    row_of_col[0] = i;
    int j0 = 0;
    std::vector<double> min_to(m + 1, inf);
    std::vector<bool> used(m + 1, false);
    do {  // grow the alternating tree until a free column is reached
      used[j0] = true;
      const int i0 = row_of_col[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double reduced = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (reduced < min_to[j]) {
          min_to[j] = reduced;
          way[j] = j0;
        }
        if (min_to[j] < delta) {
          delta = min_to[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[row_of_col[j]] += delta;
          v[j] -= delta;
        } else {
          min_to[j] -= delta;
        }
      }
      j0 = j1;
    } while (row_of_col[j0] != 0);
    do {  // flip the augmenting path
      const int j1 = way[j0];
      row_of_col[j0] = row_of_col[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> col_of_row(n, -1);
  for (int j = 1; j <= m; ++j)
    if (row_of_col[j] > 0) col_of_row[row_of_col[j] - 1] = j - 1;
  return col_of_row;
}

}  // namespace

std::vector<int> solveAssignment(const Eigen::MatrixXd& cost) {
  if (!cost.allFinite())
    throw std::invalid_argument("solveAssignment: cost matrix has non-finite entries");
  if (cost.rows() == 0) return {};
  if (cost.cols() == 0) return std::vector<int>(cost.rows(), -1);
  if (cost.rows() <= cost.cols()) return assignRowsToColumns(cost);
  // More rows than columns: solve the transpose, then invert the mapping.
  const std::vector<int> row_of_col = assignRowsToColumns(cost.transpose());
  std::vector<int> col_of_row(cost.rows(), -1);
  for (int c = 0; c < static_cast<int>(row_of_col.size()); ++c)
    if (row_of_col[c] >= 0) col_of_row[row_of_col[c]] = c;
  return col_of_row;
}

}  // namespace adugs::tracking
