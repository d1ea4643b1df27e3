#pragma once
// Numeric-vs-analytic Jacobian check for any ceres::CostFunction whose blocks may live on
// manifolds (as Basalt's test_utils): the analytic ambient Jacobian times the manifold's
// PlusJacobian is compared, block by block, with central differences of the residual along
// Plus(x, +-h e_k) in the tangent space. For a TangentCostFunction the Jacobians of
// EvaluateTangent (what the window solver uses) are compared with the same differences too. A block's error is |J_a - J_n|_F / max(|J_n|_F, 1):
// relative for Jacobians of norm above 1, absolute below.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/manifold.h>
#include <Eigen/Core>

#include "vio/estimator/tangent_cost_function.h"

namespace adugs::vio::testing {

struct JacobianCheckResult {
  bool ok = true;
  double max_error = 0.0;
  std::string report;  // one line per block: index, error, and both Jacobians when failing
};

// manifolds[k] == nullptr (or manifolds shorter than parameters): block k is Euclidean.
inline JacobianCheckResult checkJacobians(const ceres::CostFunction& cost,
                                          const std::vector<double*>& parameters,
                                          const std::vector<const ceres::Manifold*>& manifolds,
                                          double tolerance = 1e-5, double step = 1e-6) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int n_res = cost.num_residuals();
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  std::vector<RowMajor> J_amb(sizes.size());
  std::vector<double*> jac_ptrs(sizes.size());
  for (size_t k = 0; k < sizes.size(); ++k) {
    J_amb[k].resize(n_res, sizes[k]);
    jac_ptrs[k] = J_amb[k].data();
  }
  Eigen::VectorXd r0(n_res);
  JacobianCheckResult result;
  std::ostringstream report;
  if (!cost.Evaluate(parameters.data(), r0.data(), jac_ptrs.data())) {
    result.ok = false;
    result.report = "Evaluate failed";
    return result;
  }
  const auto* tangent_cost = dynamic_cast<const TangentCostFunction*>(&cost);
  std::vector<RowMajor> J_tan(sizes.size());
  if (tangent_cost) {
    std::vector<double*> tan_ptrs(sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k) {
      J_tan[k].resize(n_res, tangent_cost->tangentSize(static_cast<int>(k)));
      tan_ptrs[k] = J_tan[k].data();
    }
    Eigen::VectorXd r_t(n_res);
    if (!tangent_cost->EvaluateTangent(parameters.data(), r_t.data(), tan_ptrs.data()) ||
        (r_t - r0).norm() > 0) {
      result.ok = false;
      result.report = "EvaluateTangent failed or gave another residual";
      return result;
    }
  }
  for (size_t k = 0; k < sizes.size(); ++k) {
    const ceres::Manifold* m = k < manifolds.size() ? manifolds[k] : nullptr;
    const int tangent = m ? m->TangentSize() : sizes[k];
    Eigen::MatrixXd J_analytic = J_amb[k];
    if (m) {
      RowMajor plus(sizes[k], tangent);
      m->PlusJacobian(parameters[k], plus.data());
      J_analytic = J_amb[k] * plus;
    }
    Eigen::MatrixXd J_numeric(n_res, tangent);
    const std::vector<double> x0(parameters[k], parameters[k] + sizes[k]);
    std::vector<double> xp(sizes[k]), xm(sizes[k]);
    std::vector<double*> perturbed = parameters;
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(tangent), rp(n_res), rm(n_res);
    for (int d = 0; d < tangent; ++d) {
      for (int sign : {+1, -1}) {
        delta(d) = sign * step;
        std::vector<double>& x = sign > 0 ? xp : xm;
        if (m) {
          m->Plus(x0.data(), delta.data(), x.data());
        } else {
          for (int i = 0; i < sizes[k]; ++i) x[i] = x0[i] + delta(i);
        }
        perturbed[k] = x.data();
        cost.Evaluate(perturbed.data(), (sign > 0 ? rp : rm).data(), nullptr);
      }
      delta(d) = 0.0;
      perturbed[k] = parameters[k];
      J_numeric.col(d) = (rp - rm) / (2.0 * step);
    }
    double error = (J_analytic - J_numeric).norm() / std::max(J_numeric.norm(), 1.0);
    if (tangent_cost) {
      const double tangent_error =
          J_tan[k].cols() == J_numeric.cols()
              ? (Eigen::MatrixXd(J_tan[k]) - J_numeric).norm() / std::max(J_numeric.norm(), 1.0)
              : 1e9;
      if (tangent_error > error) J_analytic = J_tan[k];  // report the worse of the two
      error = std::max(error, tangent_error);
    }
    result.max_error = std::max(result.max_error, error);
    report << "block " << k << ": error " << error << "\n";
    if (!(error < tolerance)) {
      result.ok = false;
      report << "analytic:\n" << J_analytic << "\nnumeric:\n" << J_numeric << "\n";
    }
  }
  result.report = report.str();
  return result;
}

}  // namespace adugs::vio::testing
