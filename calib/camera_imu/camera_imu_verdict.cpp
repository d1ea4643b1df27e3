#include "calib/camera_imu/camera_imu_verdict.h"

#include <cmath>

#include "calib/text_format.h"
#include "data/formats/yaml_options.h"

namespace adugs::calib {
namespace {

constexpr double kDeg = 180.0 / M_PI;

const std::string kRotate =
    "rotate the rig briskly about every axis (roll, pitch and yaw), with the board in view, "
    "for 60 s or more";
const std::string kAccelerate =
    "move the rig back and forth along every axis as well (accelerations show the lever arm)";
const std::string kLonger = "record for longer: 60 s or more of motion in front of the board";
const std::string kClock =
    "record the IMU for the whole sequence and check that camera and IMU stamps share one clock";
const std::string kInputs =
    "check the inputs: the intrinsics and IMU noise figures of this camera and IMU, the IMU axes "
    "and units (rad/s, m/s^2)";

}  // namespace

void readCameraImuVerdictOptions(data::YamlOptionsReader& r, CameraImuVerdictOptions& o) {
  r.optional("max_translation_m", o.max_translation_m, 0.0, 1e6);
  r.optional("max_accel_bias", o.max_accel_bias, 0.0, 1e6);
  r.optional("max_gyro_bias", o.max_gyro_bias, 0.0, 1e6);
  r.optional("failed_rms_px", o.failed_rms_px, 0.0, 1e6);
  r.optional("failed_rotation_sigma_deg", o.failed_rotation_sigma_deg, 0.0, 1e6);
  r.optional("failed_translation_sigma_m", o.failed_translation_sigma_m, 0.0, 1e6);
  r.optional("failed_time_shift_sigma_s", o.failed_time_shift_sigma_s, 0.0, 1e6);
  r.optional("min_duration_s", o.min_duration_s, 0.0, 1e6);
  r.optional("min_weak_axis_rate", o.min_weak_axis_rate, 0.0, 1e6);
  r.optional("max_frames_outside_imu", o.max_frames_outside_imu, 0.0, 1.0);
  r.optional("max_rotation_sigma_deg", o.max_rotation_sigma_deg, 0.0, 1e6);
  r.optional("max_translation_sigma_m", o.max_translation_sigma_m, 0.0, 1e6);
  r.optional("max_time_shift_sigma_s", o.max_time_shift_sigma_s, 0.0, 1e6);
  r.optional("max_rms_px", o.max_rms_px, 0.0, 1e6);
}

CalibrationVerdict judgeCameraImu(const CameraImuResult& r, const CameraImuOptions& calib,
                                  const CameraImuVerdictOptions& o) {
  CalibrationVerdict v;
  // ---- what the recording holds.
  if (r.frames_with_target > 0) {
    const double share = static_cast<double>(r.frames_outside_imu) / r.frames_with_target;
    if (share > o.max_frames_outside_imu)
      v.add(Verdict::kWeak, "IMU coverage",
            strprintf("%d of %d frames with the target (%.0f %%) lie outside the IMU's time span and "
                      "were dropped",
                      r.frames_outside_imu, r.frames_with_target, 100 * share),
            kClock);
  }
  if (!r.solved) {
    v.add(Verdict::kFailed, "excitation",
          strprintf("degenerate motion: RMS rotation rate %.3f rad/s < %.3f rad/s, nothing to align "
                    "the gyro with (not solved)",
                    r.excitation(0), calib.min_rotation_rate),
          kRotate);
    return v;
  }
  if (r.excitation(2) < o.min_weak_axis_rate)
    v.add(Verdict::kWeak, "excitation",
          strprintf("the least excited rotation axis turns at %.3f rad/s RMS < %.3f rad/s (%.3f, %.3f, "
                    "%.3f): rotation about it, and the lever arm, are poorly seen",
                    r.excitation(2), o.min_weak_axis_rate, r.excitation(0), r.excitation(1),
                    r.excitation(2)),
          kRotate);
  if (r.duration_s < o.min_duration_s)
    v.add(Verdict::kWeak, "duration",
          strprintf("%.1f s of frames with the board < %.0f s", r.duration_s, o.min_duration_s),
          kLonger);

  // ---- failed: the numbers cannot describe a camera mounted next to its IMU.
  for (const std::string& f : r.solver_failures)
    v.add(r.final_solve_usable ? Verdict::kWeak : Verdict::kFailed, "solver", f, kRotate);
  if (r.final_solve_usable && !r.final_solve_converged)
    v.add(Verdict::kWeak, "solver",
          strprintf("the last solve stopped at its iteration limit (%d) still improving",
                    calib.max_iterations),
          kLonger);
  const Eigen::Vector3d p_I_C = r.T_C_I.inverse().translation();
  if (!(p_I_C.norm() <= o.max_translation_m))
    v.add(Verdict::kFailed, "plausibility",
          strprintf("the camera sits %.3f m from the IMU (> %.2f m; raise --max-translation for a "
                    "rig where it really is that far)",
                    p_I_C.norm(), o.max_translation_m),
          kRotate);
  if (!(r.accel_bias.norm() <= o.max_accel_bias))
    v.add(Verdict::kFailed, "plausibility",
          strprintf("accelerometer bias |[%.2f, %.2f, %.2f]| = %.2f m/s^2 > %.2f m/s^2 (raise "
                    "--max-accel-bias for an IMU known to be that far off)",
                    r.accel_bias(0), r.accel_bias(1), r.accel_bias(2), r.accel_bias.norm(),
                    o.max_accel_bias),
          kInputs);
  if (!(r.gyro_bias.norm() <= o.max_gyro_bias))
    v.add(Verdict::kFailed, "plausibility",
          strprintf("gyro bias |[%.3f, %.3f, %.3f]| = %.3f rad/s > %.2f rad/s (raise "
                    "--max-gyro-bias for an IMU known to be that far off)",
                    r.gyro_bias(0), r.gyro_bias(1), r.gyro_bias(2), r.gyro_bias.norm(), o.max_gyro_bias),
          kInputs);
  if (calib.estimate_time_offset && !(std::abs(r.time_shift_s) <= calib.max_time_offset_s))
    v.add(Verdict::kFailed, "plausibility",
          strprintf("time shift %.4f s left the search range +-%.3f s", r.time_shift_s,
                    calib.max_time_offset_s),
          kClock);
  if (r.corners_behind_camera > 0)
    v.add(Verdict::kFailed, "plausibility",
          strprintf("%d of %d corners lie behind the camera at the solution", r.corners_behind_camera,
                    r.corners_in_frames),
          kRotate);
  if (r.corners_used == 0 || !std::isfinite(r.reprojection_rms_px))
    v.add(Verdict::kFailed, "residuals", "no corner projects into the camera at the solution", kInputs);
  else if (r.reprojection_rms_px > o.failed_rms_px)
    v.add(Verdict::kFailed, "residuals",
          strprintf("reprojection RMS %.2f px over the %d corners used > %.2g px", r.reprojection_rms_px,
                    r.corners_used, o.failed_rms_px),
          kInputs);
  else if (r.reprojection_rms_px > o.max_rms_px)
    v.add(Verdict::kWeak, "residuals",
          strprintf("reprojection RMS %.2f px over the %d corners used > %.2g px", r.reprojection_rms_px,
                    r.corners_used, o.max_rms_px),
          kInputs);

  // ---- weak: the data do not pin the numbers down.
  if (r.has_sigma) {
    const double rot = r.sigma_rotation.maxCoeff() * kDeg;
    const double pos = r.sigma_translation.maxCoeff();
    const double shift = calib.estimate_time_offset ? r.sigma_time_shift_s : 0;
    if (rot > o.failed_rotation_sigma_deg || pos > o.failed_translation_sigma_m ||
        shift > o.failed_time_shift_sigma_s)
      v.add(Verdict::kFailed, "undetermined",
            strprintf("1-sigma rotation %.3f deg, translation %.1f mm, time shift %.3f ms (failed above "
                      "%.3g deg, %.3g mm, %.3g ms): the motion does not determine them",
                      rot, pos * 1000, shift * 1000, o.failed_rotation_sigma_deg,
                      o.failed_translation_sigma_m * 1000, o.failed_time_shift_sigma_s * 1000),
            pos > o.failed_translation_sigma_m ? kAccelerate : kRotate);
    std::string poor;
    if (rot > o.max_rotation_sigma_deg)
      poor += strprintf("rotation (1-sigma %.3f deg > %.3g deg)", rot, o.max_rotation_sigma_deg);
    if (pos > o.max_translation_sigma_m)
      poor += strprintf("%stranslation (1-sigma %.1f mm > %.3g mm)", poor.empty() ? "" : "; ",
                        pos * 1000, o.max_translation_sigma_m * 1000);
    if (calib.estimate_time_offset && r.sigma_time_shift_s > o.max_time_shift_sigma_s)
      poor += strprintf("%stime shift (1-sigma %.3f ms > %.3g ms)", poor.empty() ? "" : "; ",
                        r.sigma_time_shift_s * 1000, o.max_time_shift_sigma_s * 1000);
    if (!poor.empty())
      v.add(Verdict::kWeak, "poorly determined", poor,
            pos > o.max_translation_sigma_m ? kAccelerate : kRotate);
  } else if (calib.compute_covariance) {
    v.add(Verdict::kWeak, "covariance", "the covariance could not be computed (singular problem)",
          kRotate);
  }
  return v;
}

void judgeCameraImuInputs(CalibrationVerdict& verdict, const std::string& intrinsics_file,
                          const std::string& imu_noise_file) {
  if (!intrinsics_file.empty() && writtenVerdict(intrinsics_file) == Verdict::kWeak)
    verdict.add(Verdict::kWeak, "inputs",
                "the intrinsics (" + intrinsics_file + ") were themselves judged weak (see the top of that file)",
                "calibrate the intrinsics again from a better recording (the 'Record next' of their report)");
  if (!imu_noise_file.empty() && writtenVerdict(imu_noise_file) == Verdict::kWeak)
    verdict.add(Verdict::kWeak, "inputs",
                "the IMU noise figures (" + imu_noise_file + ") were themselves judged weak (see the top of that file)",
                "measure the IMU noise again from a longer static recording (the 'Record next' of its report)");
}

}  // namespace adugs::calib
