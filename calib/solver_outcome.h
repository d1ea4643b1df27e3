#pragma once
// Ceres as the calibrations use it: silent (its log lines never reach the user's terminal; the
// commands say what happened in their own words), and a solve's outcome as a sentence.
#include <string>

#include <ceres/solver.h>

namespace adugs::calib {

// Solver options with Ceres's own logging off (logging_type SILENT, no progress on stdout).
ceres::Solver::Options quietSolverOptions();

// What one solve achieved, in the calibration's words.
struct SolverOutcome {
  bool usable = true;      // false: the solve failed and its parameters are not a solution
  bool converged = true;   // false: stopped at the iteration limit (usable, maybe not optimal)
  std::string problem;     // empty when usable and converged, else what went wrong
};
SolverOutcome describeSolve(const ceres::Solver::Summary& summary);

// glog's minimum level for everything in the process (Ceres logs through glog: "Terminating:
// Residual and Jacobian evaluation failed." is a LOG(WARNING) inside its minimiser). Called once
// by the command line; ADUGS_SOLVER_LOG=1 in the environment keeps the solver's log for debugging.
void silenceSolverLogging();

}  // namespace adugs::calib
