#pragma once
// Minimum-cost assignment (Hungarian / Kuhn-Munkres with potentials, O(n^2 m)) for SORT's
// matching of predicted track boxes to detections. Rectangular matrices are fine: every row is
// assigned when rows <= cols, every column otherwise.
#include <Eigen/Core>
#include <vector>

namespace adugs::tracking {

// cost: rows x cols, finite values. Returns, per row, the assigned column or -1.
// Throws std::invalid_argument on non-finite costs.
std::vector<int> solveAssignment(const Eigen::MatrixXd& cost);

}  // namespace adugs::tracking
