#pragma once
// The pipeline's front-end stage, on a thread of its own: KLT feature tracking with masked-feature
// removal (vio/frontend/feature_tracker.h), the KLT start positions predicted by the gyro's
// rotation since the previous frame (with an estimator; vision-only runs track without prediction).
//
// Determinism: frame k's prediction uses the estimator's gyro bias after frame k - 2 (zero for
// the first two frames, and always without an estimator), whatever the threads' timing.
#include <Eigen/Geometry>

#include "app/pipeline/estimator_feedback.h"
#include "app/pipeline/channel.h"
#include "app/pipeline/pipeline_frame.h"
#include "data/camera_model.h"
#include "vio/frontend/feature_tracker.h"
#include "vio/imu/gyro_rotation_predictor.h"

namespace adugs::app {

class FrontEndStage {
 public:
  // T_B_C: the camera's extrinsic (its rotation turns gyro rotations into camera rotations).
  FrontEndStage(const vio::FeatureTrackerOptions& options, const data::CameraModel& camera,
                const Eigen::Isometry3d& T_B_C);

  // Until `in` is drained or `out` closed; then closes `out`. biases: nullptr without an
  // estimator. Exceptions propagate.
  void run(Channel<PipelineFrame>& in, Channel<PipelineFrame>& out, EstimatorFeedback* biases);

  static constexpr int kBiasDelay = 2;  // frame k uses the bias after frame k - 2

 private:
  vio::FeatureTracker tracker_;
  Eigen::Matrix3d R_B_C_;
  vio::GyroRotationPredictor gyro_;
};

}  // namespace adugs::app
