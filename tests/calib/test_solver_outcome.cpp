// Ceres as the calibrations use it: a failed solve described in the tool's words, and Ceres' own
// log lines ("Terminating: Residual and Jacobian evaluation failed." is a glog warning inside its
// minimiser) kept off the terminal once silenceSolverLogging() ran (adugs calls it first thing).
#include "calib/solver_outcome.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

namespace adugs::calib {
namespace {

// r = x - 1, but the cost cannot be evaluated at x < 0 (like a corner behind the camera).
struct FailsBelowZero {
  template <typename T>
  bool operator()(const T* x, T* r) const {
    if (x[0] < T(0)) return false;
    r[0] = x[0] - T(1);
    return true;
  }
};

ceres::Solver::Summary solveFrom(double start, const ceres::Solver::Options& options) {
  double x = start;
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<FailsBelowZero, 1, 1>(new FailsBelowZero), nullptr, &x);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary;
}

TEST(SolverOutcome, EvaluationFailureInOurWords) {
  const SolverOutcome ok = describeSolve(solveFrom(3.0, quietSolverOptions()));
  EXPECT_TRUE(ok.usable);
  EXPECT_TRUE(ok.converged);
  EXPECT_TRUE(ok.problem.empty());
  const SolverOutcome bad = describeSolve(solveFrom(-1.0, quietSolverOptions()));
  EXPECT_FALSE(bad.usable);
  EXPECT_NE(bad.problem.find("could not be evaluated"), std::string::npos) << bad.problem;
  EXPECT_EQ(bad.problem.find("Terminating"), std::string::npos);
  ceres::Solver::Options one = quietSolverOptions();
  one.max_num_iterations = 1;
  double x = 30;
  ceres::Problem problem;  // a cost that needs more than one step
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<FailsBelowZero, 1, 1>(new FailsBelowZero),
                           new ceres::CauchyLoss(0.1), &x);
  ceres::Solver::Summary summary;
  ceres::Solve(one, &problem, &summary);
  const SolverOutcome stopped = describeSolve(summary);
  EXPECT_TRUE(stopped.usable);
  EXPECT_FALSE(stopped.converged);
  EXPECT_NE(stopped.problem.find("did not converge"), std::string::npos);
}

TEST(SolverOutcome, CeresLogLinesAreSilenced) {
  ceres::Solver::Options loud;  // Ceres' defaults: it logs its termination
  testing::internal::CaptureStderr();
  solveFrom(-1.0, loud);
  const std::string before = testing::internal::GetCapturedStderr();
  EXPECT_NE(before.find("Terminating"), std::string::npos) << "Ceres no longer logs this? " << before;
  silenceSolverLogging();
  testing::internal::CaptureStderr();
  solveFrom(-1.0, loud);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace adugs::calib
