#include "app/pipeline/frontend_stage.h"

#include <chrono>

namespace adugs::app {

FrontEndStage::FrontEndStage(const vio::FeatureTrackerOptions& options, const data::CameraModel& camera,
                             const Eigen::Isometry3d& T_B_C)
    : tracker_(options, camera), R_B_C_(T_B_C.rotation()) {}

void FrontEndStage::run(Channel<PipelineFrame>& in, Channel<PipelineFrame>& out, EstimatorFeedback* biases) {
  PipelineFrame f;
  int64_t previous_t = -1;
  while (in.pop(&f)) {
    if (biases)
      for (const data::ImuSample& s : f.imu) gyro_.addImu(s);
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
    if (biases && !biases->waitFor(f.index - kBiasDelay, &gyro_bias)) break;  // the estimator stopped
    if (biases && previous_t >= 0) {  // without an estimator there is no IMU to predict from
      tracker_.setPredictedRotation(gyro_.cameraRotation(previous_t, f.frame.t_ns, gyro_bias, R_B_C_));
      gyro_.dropBefore(f.frame.t_ns);
    }
    const auto t0 = std::chrono::steady_clock::now();
    f.features = tracker_.trackFrame(f.frame.t_ns, f.frame.image, f.mask);
    f.frontend_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    f.dropped_dynamic = tracker_.lastStats().dropped_dynamic;
    f.dropped_points = tracker_.lastDroppedDynamic();
    previous_t = f.frame.t_ns;
    if (!out.push(std::move(f))) break;
  }
  out.close();
}

}  // namespace adugs::app
