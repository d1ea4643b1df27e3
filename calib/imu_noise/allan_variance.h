#pragma once
// IMU noise from a static recording: overlapping Allan deviation on log-spaced cluster times,
// and a fit of the two noise terms Kalibr's imu.yaml needs, per axis:
//   white noise density N (the slope -1/2 line, read at tau = 1 s) and
//   bias random walk K   (the slope +1/2 line, read at tau = 3 s),
// from the model AVAR(tau) = N^2 / tau + K^2 tau / 3 fitted by non-negative least squares in
// relative error, weighted by each point's number of independent clusters. Bias instability B
// (reported, not in imu.yaml) is the curve's minimum / sqrt(2 ln 2 / pi).
// The sensor figure is the mean over the three axes.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "calib/kalibr_yaml.h"

namespace adugs::calib {

struct ImuRecording {
  std::vector<int64_t> t_ns;
  std::vector<Eigen::Vector3d> gyro;   // rad/s
  std::vector<Eigen::Vector3d> accel;  // m/s^2
  double rate_hz = 0;                  // from the median sample interval
};

// EuRoC/ASL imu0/data.csv (data::readEurocImuCsv: errors name file, line and column), with the
// sample rate from the median interval.
ImuRecording readImuCsv(const std::string& path);

struct AllanCurve {
  std::vector<double> tau;              // s
  std::vector<Eigen::Vector3d> adev;    // per axis, sensor units
  std::vector<int> clusters;            // number of overlapping clusters behind each point
};

// Overlapping Allan deviation of samples taken every dt seconds, at about `points` log-spaced
// cluster sizes from 1 sample to a tenth of the recording (longer clusters are too few to help:
// in simulation they biased the random walk low).
AllanCurve allanDeviation(const std::vector<Eigen::Vector3d>& samples, double dt, int points = 60);

struct AxisFit {
  double white = 0;        // N
  double instability = 0;  // B, from the minimum of the curve
  double random_walk = 0;  // K
};

struct SensorNoise {
  AllanCurve curve;
  AxisFit axis[3];
  double white = 0;        // mean over axes
  double random_walk = 0;
};

// independent: number of independent clusters behind each point (weights); empty = equal.
AxisFit fitAllan(const std::vector<double>& tau, const std::vector<double>& adev,
                 const std::vector<double>& independent = {});

struct AllanOptions {
  int points = 60;
};

struct ImuNoiseResult {
  SensorNoise gyro, accel;
  ImuNoiseFigures figures;
  double duration_s = 0;
  size_t samples = 0;
};

// Throws data::InputError when the recording is too short (< 1000 samples).
ImuNoiseResult estimateImuNoise(const ImuRecording& rec, const AllanOptions& options = {});

// verdict_block: the verdict as text (formatVerdict), printed after the inputs.
std::string formatImuNoiseReport(const ImuNoiseResult& r, const std::string& input, double seconds,
                                 const std::string& verdict_block = "");
// Log-log plot of both sensors' Allan deviations per axis with the fitted lines.
cv::Mat renderAllanPlot(const ImuNoiseResult& r);

}  // namespace adugs::calib
