#pragma once
// Can IMU noise figures from an Allan analysis be trusted? The recording must be static (a
// moving IMU's Allan deviation is the motion's, not the noise's) and long enough for the random
// walk to show: turned into a verdict (calib/calibration_verdict.h). How each default bound was
// chosen: doc/calibration.md, "Verdicts".
#include "calib/calibration_verdict.h"
#include "calib/imu_noise/allan_variance.h"

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::calib {

struct ImuNoiseVerdictOptions {
  // failed above: the IMU moved (a static MEMS IMU shows 1e-4..1e-3 rad/s and 1e-3..1e-2 m/s^2
  // at tau = 1 s; a hand-held or flying one 0.1..1).
  double max_static_gyro_adev = 0.01;   // rad/s, Allan deviation at tau = 1 s
  double max_static_accel_adev = 0.1;   // m/s^2
  // failed below: the random walk's read-out point (tau = 3 s) is beyond the longest cluster
  // time (a tenth of the recording).
  double failed_duration_s = 30;
  // weak below: the longest cluster time over the white-noise / random-walk crossover
  // sqrt(3) N / K (randomWalkVisibility); below it K rests on a few long clusters.
  double min_random_walk_visibility = 5;
};

// Reads the keys above (unknown keys are InputError; the caller calls finish()).
void readImuNoiseVerdictOptions(data::YamlOptionsReader& r, ImuNoiseVerdictOptions& o);

// tau_max / tau_c: the longest cluster time (a tenth of the recording) over the cluster time
// where the random walk's slope +1/2 line crosses the white noise's -1/2 line, sqrt(3) N / K
// (mean figures). 0 when no random walk was found, +infinity when no white noise was.
double randomWalkVisibility(const SensorNoise& noise, double duration_s);

CalibrationVerdict judgeImuNoise(const ImuNoiseResult& result,
                                 const ImuNoiseVerdictOptions& options = {});

}  // namespace adugs::calib
