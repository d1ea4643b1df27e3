#include "calib/solver_outcome.h"

#include <cstdlib>

#include <glog/logging.h>

#include "calib/text_format.h"

namespace adugs::calib {

ceres::Solver::Options quietSolverOptions() {
  ceres::Solver::Options o;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  return o;
}

SolverOutcome describeSolve(const ceres::Solver::Summary& summary) {
  SolverOutcome out;
  if (summary.termination_type == ceres::NO_CONVERGENCE) {
    out.converged = false;
    out.problem = strprintf("did not converge within %zu iterations",
                            summary.iterations.empty() ? size_t{0} : summary.iterations.size() - 1);
  }
  if (summary.IsSolutionUsable()) return out;
  out.usable = false;
  out.converged = false;
  const std::string& m = summary.message;
  if (m.find("Residual and Jacobian evaluation failed") != std::string::npos ||
      m.find("evaluation failed") != std::string::npos)
    out.problem =
        "the reprojection could not be evaluated at the current estimate (target corners "
        "project behind the camera or outside the lens model): the start was too far off";
  else if (m.find("inear solver") != std::string::npos)
    out.problem = "the linear solver failed: the data do not fix every parameter";
  else if (summary.termination_type == ceres::FAILURE && m.empty())
    out.problem = "the solver failed";
  else
    out.problem = "the solver failed (" + m + ")";
  return out;
}

void silenceSolverLogging() {
  const char* keep = std::getenv("ADUGS_SOLVER_LOG");
  if (keep && *keep && std::string(keep) != "0") return;
  FLAGS_minloglevel = google::GLOG_FATAL;
}

}  // namespace adugs::calib
