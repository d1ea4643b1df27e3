#include "vio/init/sfm_geometry.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>

namespace adugs::vio {
namespace {

Eigen::Vector3d bearing(const Eigen::Vector2d& normalized) {
  return normalized.homogeneous().normalized();
}

Eigen::Vector3d toCamera(const SfmPose& pose, const Eigen::Vector3d& point_R) {
  return pose.R_R_C.transpose() * (point_R - pose.p_R_C);
}

}  // namespace

bool triangulateLinear(const std::vector<SfmView>& views, Eigen::Vector3d* point_R) {
  if (views.size() < 2) return false;
  // Each view gives x (P3 X) = P1 X and y (P3 X) = P2 X with P = [R^T | -R^T p] (reference ->
  // camera).
  Eigen::MatrixXd A(2 * views.size(), 4);
  for (size_t k = 0; k < views.size(); ++k) {
    Eigen::Matrix<double, 3, 4> P;
    P.leftCols<3>() = views[k].pose->R_R_C.transpose();
    P.col(3) = -views[k].pose->R_R_C.transpose() * views[k].pose->p_R_C;
    A.row(2 * k) = views[k].normalized.x() * P.row(2) - P.row(0);
    A.row(2 * k + 1) = views[k].normalized.y() * P.row(2) - P.row(1);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  if (!X.allFinite() || std::abs(X(3)) < 1e-12) return false;
  const Eigen::Vector3d point = X.head<3>() / X(3);
  for (const auto& view : views)
    if (toCamera(*view.pose, point).z() < 1e-6) return false;
  *point_R = point;
  return point.allFinite();
}

Eigen::Matrix3d bestFitRotation(const std::vector<Eigen::Vector2d>& normalized1,
                                const std::vector<Eigen::Vector2d>& normalized2) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < normalized1.size(); ++k)
    H += bearing(normalized2[k]) * bearing(normalized1[k]).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;  // no reflection
  return svd.matrixU() * D * svd.matrixV().transpose();
}

double rotationCompensatedParallax(const std::vector<Eigen::Vector2d>& normalized1,
                                   const std::vector<Eigen::Vector2d>& normalized2) {
  if (normalized1.empty()) return 0.0;
  const Eigen::Matrix3d R = bestFitRotation(normalized1, normalized2);
  double sum = 0.0;
  for (size_t k = 0; k < normalized1.size(); ++k) {
    const Eigen::Vector3d rotated = R * bearing(normalized1[k]);
    sum += std::atan2(rotated.cross(bearing(normalized2[k])).norm(),
                      rotated.dot(bearing(normalized2[k])));
  }
  return sum / static_cast<double>(normalized1.size());
}

double meanDisplacement(const std::vector<Eigen::Vector2d>& normalized1,
                        const std::vector<Eigen::Vector2d>& normalized2) {
  if (normalized1.empty()) return 0.0;
  double sum = 0.0;
  for (size_t k = 0; k < normalized1.size(); ++k) sum += (normalized2[k] - normalized1[k]).norm();
  return sum / static_cast<double>(normalized1.size());
}

double reprojectionError(const SfmPose& pose, const Eigen::Vector3d& point_R,
                         const Eigen::Vector2d& normalized) {
  const Eigen::Vector3d p_C = toCamera(pose, point_R);
  if (p_C.z() <= 1e-9) return std::numeric_limits<double>::infinity();
  return (p_C.head<2>() / p_C.z() - normalized).norm();
}

}  // namespace adugs::vio
