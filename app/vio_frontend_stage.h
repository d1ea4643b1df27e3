#pragma once
// The first stage of `adugs run`'s two-thread pipeline: reads the sequence (image decoding),
// makes the frame's dynamic mask (none, the simulator's ground truth, or detector -> SORT ->
// segmentation), and tracks features with a gyro-predicted rotation. It runs one frame ahead of
// the estimator (second stage, main thread), which sends back the gyro bias after each frame.
//
// Determinism: frame k's prediction always uses the bias the estimator had after frame k - 2
// (zero for the first two), whatever the threads' timing, so runs are reproducible.
#include <Eigen/Core>
#include <memory>
#include <string>

#include "app/overlay_video.h"
#include "tracking/dynamic_masker.h"
#include <vector>

#include "app/pipeline_channel.h"
#include "data/camera_model.h"
#include "data/sequence_source.h"
#include "vio/frontend/feature_tracker.h"
#include "vio/frontend/gyro_rotation_predictor.h"

namespace adugs::tracking {
class Detector;
class DynamicMasker;
}  // namespace adugs::tracking

namespace adugs::app {

// What the front-end hands the estimator for one frame.
struct TrackedFrame {
  std::vector<data::ImuSample> imu;  // samples since the previous frame, in time order
  vio::FrameFeatures features;
  double sequence_s = 0;  // since the first measurement
  double frontend_ms = 0;
  double mask_ms = -1;  // < 0: no detector mask computed
  // Detector masks scored against the simulator's exact masks (when the sequence has them):
  // pixels of the exact mask, of those covered, and masked in all.
  double exact_pixels = 0, exact_covered = 0, masked_pixels = 0;
  double masked_fraction = 0;
  int dropped_dynamic = 0;
};

struct FrontEndStageOptions {
  std::string mask = "none";  // none | gt | detector
  std::string mask_dir;       // --mask gt: the simulator's mask0/data folder
  std::string detector_model, segmenter = "grabcut", sam_encoder, sam_decoder;
  std::string detector_config;  // darknet .cfg ("" = beside the .weights)
  tracking::DynamicMaskerOptions masker;  // SORT, detect_every, refinement (run config's dynamic:)
  std::string overlay_path;  // non-empty: the overlay video (app/overlay_video.h) of every frame
};

class FrontEndStage {
 public:
  // T_B_C: the camera's extrinsic (its rotation turns gyro rotations into camera rotations).
  FrontEndStage(data::SequenceSource& source, const vio::FeatureTrackerOptions& tracker_options,
                const data::CameraModel& camera, const Eigen::Isometry3d& T_B_C,
                const FrontEndStageOptions& options);
  ~FrontEndStage();

  // Runs to the end of the sequence, then closes `frames`. Stops early (without error) when
  // either channel is closed by the estimator side. Exceptions propagate to the caller.
  void run(Channel<TrackedFrame>& frames, Channel<Eigen::Vector3d>& gyro_biases);

  int imuSamples() const { return imu_samples_; }
  int64_t firstTimeNs() const { return first_t_; }  // of the first measurement, -1 before

 private:
  // previous_t: the previous frame's stamp (-1 for the first frame).
  cv::Mat makeMask(const data::Frame& frame, int64_t previous_t, TrackedFrame* out);
  void writeOverlay(const data::Frame& frame, const cv::Mat& mask, const TrackedFrame& out);

  data::SequenceSource& source_;
  vio::FeatureTracker tracker_;
  Eigen::Matrix3d R_B_C_;
  FrontEndStageOptions options_;
  std::unique_ptr<tracking::Detector> detector_;
  std::unique_ptr<tracking::DynamicMasker> masker_;
  std::vector<tracking::TrackedObject> last_objects_;  // the masker's boxes of the current frame
  std::unique_ptr<OverlayVideo> overlay_;
  vio::GyroRotationPredictor gyro_;
  data::CameraModel camera_;
  Eigen::Vector3d last_gyro_bias_ = Eigen::Vector3d::Zero();  // the estimator's latest, for SORT's compensation
  int imu_samples_ = 0;
  int64_t first_t_ = -1;
};

}  // namespace adugs::app
