#pragma once
// Outputs of the camera-IMU calibration: Kalibr camchain-imucam.yaml, a text report and plots.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

#include "calib/calibration_verdict.h"
#include "calib/camera_imu/camera_imu_calibrator.h"

namespace adugs::calib {

// Kalibr camchain-imucam.yaml: the camchain block of the camera plus T_cam_imu (4x4, row-major
// nested lists as Kalibr writes them) and timeshift_cam_imu.
std::string formatCamchainImuCamYaml(const CalibCamera& camera, const CameraImuResult& result,
                                     const std::string& camera_name = "cam0",
                                     const std::string& rostopic = "/cam0/image_raw");

struct CameraImuReportContext {
  std::string corners_input, imu_input, intrinsics_input;
  bool has_reference = false;
  std::string reference_name;
  Eigen::Isometry3d reference_T_I_C = Eigen::Isometry3d::Identity();  // EuRoC T_BS
};

// Rotation angle [deg] and translation distance [m] between two transforms.
void compareTransforms(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double& angle_deg,
                       double& distance_m);

// The report, with the verdict's block after the inputs.
std::string formatCameraImuReport(const CameraImuResult& result, const CameraImuOptions& options,
                                  const CalibrationVerdict& verdict,
                                  const CameraImuReportContext& context);

// Residuals (x, y, z) over time, one panel per axis, with the +-3 sigma lines.
cv::Mat renderImuResidualPlot(const std::vector<TimedVector>& residuals, const std::string& title,
                              const std::string& unit, double sigma);
// Histogram of the corner reprojection errors (px).
cv::Mat renderReprojectionHistogram(const std::vector<double>& errors_px);

}  // namespace adugs::calib
