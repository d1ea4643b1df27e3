// SO(3) helpers: exp/log round trip and the right Jacobian against finite differences.
#include "vio/imu/so3.h"

#include <cmath>

#include <gtest/gtest.h>

namespace adugs::vio {
namespace {

TEST(So3, SkewIsCrossProduct) {
  const Eigen::Vector3d a(0.3, -1.2, 2.0), b(-0.7, 0.4, 1.1);
  EXPECT_TRUE((skew(a) * b).isApprox(a.cross(b), 1e-15));
}

TEST(So3, LogInvertsExpIncludingNearPiAndTiny) {
  for (const Eigen::Vector3d& phi : {Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(1e-9, 2e-9, 0),
                                    Eigen::Vector3d(0, 0, M_PI - 1e-6), Eigen::Vector3d(2, 1, -0.5)}) {
    EXPECT_LT((quaternionLog(quaternionExp(phi)) - phi).norm(), 1e-9 * std::max(1.0, phi.norm()));
  }
  // -q is the same rotation: the log must not change.
  const Eigen::Quaterniond q = quaternionExp(Eigen::Vector3d(0.4, 0.1, -0.2));
  Eigen::Quaterniond minus_q;
  minus_q.coeffs() = -q.coeffs();
  EXPECT_LT((quaternionLog(minus_q) - quaternionLog(q)).norm(), 1e-12);
}

TEST(So3, RightJacobianMatchesFiniteDifferencesAndInverse) {
  for (const Eigen::Vector3d& phi : {Eigen::Vector3d(0.3, -0.5, 0.8), Eigen::Vector3d(1e-8, 0, 1e-8)}) {
    // Exp(phi + d) = Exp(phi) Exp(Jr d)  =>  Jr e_k = Log(Exp(phi)^-1 Exp(phi + h e_k)) / h.
    const double h = 1e-6;
    Eigen::Matrix3d Jn;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
      Jn.col(k) = (quaternionLog(quaternionExp(phi).conjugate() * quaternionExp(phi + e)) -
                   quaternionLog(quaternionExp(phi).conjugate() * quaternionExp(phi - e))) / (2 * h);
    }
    EXPECT_LT((rightJacobian(phi) - Jn).norm(), 1e-8);
    EXPECT_LT((rightJacobianInverse(phi) * rightJacobian(phi) - Eigen::Matrix3d::Identity()).norm(),
              1e-12);
  }
}

}  // namespace
}  // namespace adugs::vio
