#pragma once
// Small geometric pieces of the initialization SfM, on undistorted normalised coordinates
// (x, y) = (X / Z, Y / Z) and camera poses T_R_C (camera C in a reference camera frame R).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace adugs::vio {

// A camera pose in the SfM reference frame: p_R = R_R_C * p_C + p_R_C.
struct SfmPose {
  Eigen::Matrix3d R_R_C = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_R_C = Eigen::Vector3d::Zero();
};

// One view of a point: the pose of the camera and the normalised observation.
struct SfmView {
  const SfmPose* pose = nullptr;
  Eigen::Vector2d normalized;
};

// Linear (DLT) triangulation from >= 2 views. false if the views are too few, the system is
// degenerate, or the point lies behind (or within 1e-6 of) any of the cameras.
bool triangulateLinear(const std::vector<SfmView>& views, Eigen::Vector3d* point_R);

// Rotation R minimising sum |b2_k - R b1_k|^2 over unit bearings (Kabsch / Procrustes, SVD).
// It explains as much of the feature motion as a pure rotation can.
Eigen::Matrix3d bestFitRotation(const std::vector<Eigen::Vector2d>& normalized1,
                                const std::vector<Eigen::Vector2d>& normalized2);

// Mean angle (rad) between b2_k and R b1_k: the feature motion a rotation cannot explain,
// i.e. the translation-induced parallax. Multiply by the focal length for pixels.
double rotationCompensatedParallax(const std::vector<Eigen::Vector2d>& normalized1,
                                   const std::vector<Eigen::Vector2d>& normalized2);

// Mean |x2 - x1| (normalised units) over index-aligned points: the raw feature motion.
double meanDisplacement(const std::vector<Eigen::Vector2d>& normalized1,
                        const std::vector<Eigen::Vector2d>& normalized2);

// Reprojection error of point_R in the view, in normalised units (infinite if behind).
double reprojectionError(const SfmPose& pose, const Eigen::Vector3d& point_R,
                         const Eigen::Vector2d& normalized);

}  // namespace adugs::vio
