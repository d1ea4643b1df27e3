#pragma once
// Visual-inertial alignment of an up-to-scale SfM window with the preintegrated IMU
// (VINS-Mono, Qin et al. 2018, section V-B). Frames k = 0..n-1, c0 = the first camera frame:
//   R_c0_bk = R_c0_ck R_B_C^T,   s p_c0_bk = s pbar_c0_ck - R_c0_bk p_B_C   (s: metric / SfM)
// Preintegration k -> k+1 (dt), with v_k expressed in body frame b_k and g_c0 the gravity vector:
//   alpha = R_k^T (s (pbar_c_{k+1} - pbar_c_k) - R_{k+1} p_BC + R_k p_BC) - v_k dt - R_k^T g dt^2/2
//   beta  = R_k^T R_{k+1} v_{k+1} - v_k - R_k^T g dt
// Both linear in x = [v_0 .. v_{n-1}, g_c0, s].
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "vio/imu/imu_preintegration.h"

namespace adugs::vio {

constexpr double kInitGravityNorm = 9.81;

// One frame of the alignment: its SfM pose (camera in c0, SfM scale) and the IMU since the
// previous frame (nullptr for frame 0).
struct AlignmentFrame {
  Eigen::Matrix3d R_c0_c = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_c0_c = Eigen::Vector3d::Zero();
  std::shared_ptr<ImuPreintegration> imu_from_previous;
};

// Gyro bias from the SfM relative body rotations: min sum |Log(gamma_k(bg)^-1 q_sfm_k)|^2 with
// gamma_k(bg) = gamma_k * Exp(J_k (bg - bg0_k)) linearised around each preintegration's own bias
// bg0_k (Jacobian dq/dbg), so preintegrations with different linearisation biases mix correctly.
// Returns the absolute bias (one Gauss-Newton step). false on a singular system.
bool solveGyroBias(const std::vector<AlignmentFrame>& frames, const Eigen::Matrix3d& R_B_C,
                   Eigen::Vector3d* gyro_bias);

struct LinearAlignment {
  std::vector<Eigen::Vector3d> velocities_body;  // v_k in b_k
  Eigen::Vector3d gravity_c0 = Eigen::Vector3d::Zero();
  double scale = 0;
  // Standard deviation of the scale from the least-squares fit itself: sigma^2 (A^T A)^-1_ss with
  // sigma^2 = |A x - b|^2 / (rows - unknowns). Large when the IMU barely accelerated (the scale
  // column is nearly dependent on the others) or when the SfM trajectory and the IMU disagree (a
  // window whose SfM followed moving objects); 0 when there is no redundancy to estimate it from.
  double scale_std = 0;
};

// Unconstrained linear solve of [v_k, g_c0, s] (uses the preintegrations' deltaP/deltaV as they
// are). false on a singular system or a non-finite solution.
bool solveLinearAlignment(const std::vector<AlignmentFrame>& frames, const Eigen::Isometry3d& T_B_C,
                          LinearAlignment* out);

// Residual A x - b of the stacked alignment equations (6 per interval: alpha rows, then beta
// rows) at a given solution; zero for the exact one.
Eigen::VectorXd alignmentResidual(const std::vector<AlignmentFrame>& frames,
                                  const Eigen::Isometry3d& T_B_C, const LinearAlignment& solution);

// Same with |g| fixed: g = |g| g0/|g0| + B w on the 2-D tangent basis B of g0, iterated.
bool refineGravity(const std::vector<AlignmentFrame>& frames, const Eigen::Isometry3d& T_B_C,
                   const Eigen::Vector3d& gravity_c0_guess, int iterations, LinearAlignment* out);

// IMU excitation (VINS-Mono's check): per-axis std, over the intervals, of the mean specific
// force deltaV / dt in each interval's start body frame; the largest axis. A body at rest (or one
// whose images move while the IMU does not) gives only the sensor noise; scale is then
// unobservable.
double imuExcitation(const std::vector<AlignmentFrame>& frames);

// Standard deviation of unknown `unknown` of the least-squares solution x of A x = b, with the
// noise level estimated from the fit: sqrt(sigma^2 (A^T A)^-1_uu), sigma^2 = |A x - b|^2 /
// (rows - columns). 0 without redundancy (rows <= columns: nothing to estimate sigma from),
// infinity on a singular A^T A (the unknown is undetermined).
double leastSquaresStd(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                       Eigen::Index unknown);

// Two unit vectors orthogonal to g and to each other (columns).
Eigen::Matrix<double, 3, 2> tangentBasis(const Eigen::Vector3d& g);

// R_W_c0 mapping gravity_c0 onto (0, 0, -|g|) and giving the first body (R_c0_b0) zero yaw.
Eigen::Matrix3d worldFromFirstCamera(const Eigen::Vector3d& gravity_c0,
                                     const Eigen::Matrix3d& R_c0_b0);

}  // namespace adugs::vio
