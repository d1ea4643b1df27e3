#include "vio/init/visual_inertial_initializer.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "vio/init/visual_inertial_alignment.h"
#include "vio/init/visual_sfm.h"

namespace adugs::vio {
namespace {

// Checks the window before any maths; "" when usable.
std::string validateWindow(const std::vector<InitFrame>& frames, const InitOptions& options) {
  std::ostringstream why;
  if (static_cast<int>(frames.size()) < std::max(options.min_frames, 2)) {
    why << "too few frames: " << frames.size() << " (need " << std::max(options.min_frames, 2)
        << ")";
    return why.str();
  }
  for (size_t k = 0; k < frames.size(); ++k) {
    const InitFrame& f = frames[k];
    if (f.ids.size() != f.normalized.size()) {
      why << "frame " << k << ": " << f.ids.size() << " ids but " << f.normalized.size()
          << " points";
      return why.str();
    }
    for (const auto& p : f.normalized)
      if (!p.allFinite()) {
        why << "frame " << k << ": non-finite feature coordinate";
        return why.str();
      }
    if (k > 0 && f.t_ns <= frames[k - 1].t_ns) {
      why << "frame " << k << ": timestamps do not increase";
      return why.str();
    }
    if (k == 0) continue;
    const auto& imu = f.imu_from_previous;
    if (!imu || imu->samples().size() < 2 || imu->sumDt() <= 0) {
      why << "frame " << k << ": no IMU preintegration from the previous frame";
      return why.str();
    }
    if (!imu->deltaP().allFinite() || !imu->deltaV().allFinite() ||
        !imu->deltaQ().coeffs().allFinite()) {
      why << "frame " << k << ": non-finite IMU preintegration";
      return why.str();
    }
  }
  return "";
}

std::string number(double value) {
  std::ostringstream out;
  out.precision(4);
  out << value;
  return out.str();
}

InitResult initialize(std::vector<InitFrame>& frames, const Eigen::Isometry3d& T_B_C,
                      const InitOptions& options) {
  InitResult result;
  auto fail = [&result](const std::string& why) {
    result = InitResult();
    result.failure_reason = why;
    return result;
  };
  if (const std::string why = validateWindow(frames, options); !why.empty()) return fail(why);
  if (!T_B_C.matrix().allFinite()) return fail("non-finite camera-IMU extrinsic");
  const int n = static_cast<int>(frames.size());

  // 1. Vision-only SfM (up to scale, in the first camera frame c0).
  std::vector<SfmFrameObservations> observations(n);
  for (int k = 0; k < n; ++k) observations[k] = {frames[k].ids, frames[k].normalized};
  VisualSfmOptions sfm_options;
  sfm_options.min_common_features = options.min_common_features;
  sfm_options.min_parallax_px = options.min_parallax_px;
  sfm_options.focal_px = options.focal_px;
  sfm_options.max_reprojection_px = options.max_reprojection_px;
  const VisualSfmResult sfm = runVisualSfm(observations, sfm_options);
  if (!sfm.success) return fail(sfm.failure_reason);

  std::vector<AlignmentFrame> alignment(n);
  for (int k = 0; k < n; ++k) {
    alignment[k].R_c0_c = sfm.poses[k].R_R_C;
    alignment[k].p_c0_c = sfm.poses[k].p_R_C;
    alignment[k].imu_from_previous = frames[k].imu_from_previous;
  }
  // Checked after the SfM, whose parallax failure is the more telling reason when nothing moves.
  if (const double excitation = imuExcitation(alignment); excitation < options.min_imu_excitation)
    return fail("IMU excitation " + number(excitation) + " m/s^2 below " +
                number(options.min_imu_excitation) + ": the IMU barely moved, scale unobservable");

  // 2. Gyro bias: solve, repropagate with it, solve again around the new linearisation point.
  const Eigen::Matrix3d R_BC = T_B_C.rotation();
  Eigen::Vector3d gyro_bias;
  for (int pass = 0; pass < 2; ++pass) {
    if (!solveGyroBias(alignment, R_BC, &gyro_bias))
      return fail("gyro bias: singular system (no rotation information)");
    if (!gyro_bias.allFinite() || gyro_bias.norm() > options.max_gyro_bias)
      return fail("gyro bias " + number(gyro_bias.norm()) + " rad/s above " +
                  number(options.max_gyro_bias));
    for (int k = 1; k < n; ++k)
      frames[k].imu_from_previous->repropagate(frames[k].imu_from_previous->linearizedAccelBias(),
                                               gyro_bias);
  }

  // 3. Velocities, gravity and scale; then |g| fixed.
  LinearAlignment linear;
  if (!solveLinearAlignment(alignment, T_B_C, &linear))
    return fail("visual-inertial alignment: singular linear system (too little motion?)");
  if (!(linear.scale > options.min_scale))
    return fail("visual-inertial alignment: scale " + number(linear.scale) +
                " not above the minimum " + number(options.min_scale));
  if (std::abs(linear.gravity_c0.norm() - kInitGravityNorm) > options.gravity_norm_tolerance)
    return fail("visual-inertial alignment: |g| = " + number(linear.gravity_c0.norm()) +
                " m/s^2, too far from 9.81 (tolerance " + number(options.gravity_norm_tolerance) +
                ")");
  LinearAlignment refined;
  if (!refineGravity(alignment, T_B_C, linear.gravity_c0, 4, &refined))
    return fail("gravity refinement: singular linear system");
  if (!(refined.scale > options.min_scale))
    return fail("gravity refinement: scale " + number(refined.scale) + " not above the minimum " +
                number(options.min_scale));
  const double scale_relative_std = refined.scale_std / refined.scale;
  if (options.max_scale_relative_std > 0 && scale_relative_std > options.max_scale_relative_std) {
    fail("visual-inertial alignment: scale uncertain (std " + number(100 * scale_relative_std) +
         " % of the scale, above " + number(100 * options.max_scale_relative_std) +
         " %): the images and the IMU disagree or the IMU barely accelerated");
    result.scale_relative_std = scale_relative_std;
    return result;
  }

  // 4. Gravity-aligned metric world: origin at the first body, first body yaw kept (zero).
  const double s = refined.scale;
  const Eigen::Vector3d p_BC = T_B_C.translation();
  auto bodyRotation = [&](int k) -> Eigen::Matrix3d {
    return sfm.poses[k].R_R_C * R_BC.transpose();
  };
  auto bodyPosition = [&](int k) -> Eigen::Vector3d {
    return s * sfm.poses[k].p_R_C - bodyRotation(k) * p_BC;
  };
  const Eigen::Matrix3d R_W_c0 = worldFromFirstCamera(refined.gravity_c0, bodyRotation(0));
  const Eigen::Vector3d p_c0_b0 = bodyPosition(0);
  for (int k = 0; k < n; ++k) {
    data::StampedPose pose;
    pose.t_ns = frames[k].t_ns;
    const Eigen::Matrix3d R_W_B = R_W_c0 * bodyRotation(k);
    pose.q_W_B = Eigen::Quaterniond(R_W_B).normalized();
    pose.p_W_B = R_W_c0 * (bodyPosition(k) - p_c0_b0);
    result.poses.push_back(pose);
    result.velocities_W.push_back(R_W_B * refined.velocities_body[k]);
  }
  for (const auto& [id, point] : sfm.points)
    result.landmarks_W[id] = R_W_c0 * (s * point - p_c0_b0);
  result.gyro_bias = gyro_bias;
  result.accel_bias = frames[1].imu_from_previous->linearizedAccelBias();
  result.scale = s;
  result.scale_relative_std = scale_relative_std;

  for (const auto& pose : result.poses)
    if (!pose.p_W_B.allFinite() || !pose.q_W_B.coeffs().allFinite()) return fail("non-finite pose");
  for (const auto& v : result.velocities_W)
    if (!v.allFinite()) return fail("non-finite velocity");
  result.success = true;
  return result;
}

}  // namespace

InitResult initializeVisualInertial(std::vector<InitFrame>& frames, const Eigen::Isometry3d& T_B_C,
                                    const InitOptions& options) {
  // The contract is "never throws": a library error on strange input becomes a failure reason.
  try {
    return initialize(frames, T_B_C, options);
  } catch (const std::exception& e) {
    InitResult result;
    result.failure_reason = std::string("initialization error: ") + e.what();
    return result;
  }
}

}  // namespace adugs::vio
