#pragma once
// The pipeline's dynamic-mask stage, on a thread of its own: per frame no mask, the simulator's
// ground-truth mask (mav0/mask0), or the paper's chain after the detector (which runs in the stage
// before, app/pipeline/detection_stage.h): enhanced SORT -> box segmentation -> refinement
// (tracking/dynamic_masker.h), on the frame's colour image when the source has one.
//
// The motion cue runs on every frame, so with it the masker takes the detector's boxes (on the
// frames it ran on) and the cue's together on every frame.
// The motion cue, and the masker's camera-motion compensation when on, take the gyro rotation
// since the previous frame with the estimator's bias after frame k - 3 (app/pipeline/estimator_feedback.h): one frame further
// back than the front-end's, so this stage can work a frame ahead of it. The cue's translation
// between frames k - 1 and k is the estimator's state after frame k - 3 carried to both by the IMU
// (vio/imu/imu_state_predictor.h): the velocity three frames old turns with the platform.
#include <Eigen/Geometry>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/pipeline/estimator_feedback.h"
#include "app/pipeline/channel.h"
#include "app/pipeline/mask_source.h"
#include "app/pipeline/pipeline_frame.h"
#include "data/camera_model.h"
#include "data/formats/mot_io.h"
#include "tracking/detect/motion_cue.h"
#include "tracking/dynamic_masker.h"
#include "vio/imu/gyro_rotation_predictor.h"
#include "vio/imu/imu_state_predictor.h"

namespace adugs::app {

struct MaskingOptions {
  MaskSource source = MaskSource::kNone;
  std::string mask_dir;       // the simulator's mav0/mask0/data folder ("" if the sequence has none)
  std::string objects_path;   // its mav0/objects0/gt.txt: the recall per mover class ("" if none)
  std::string detector_model, detector_config;  // for the detection stage; darknet .cfg ("" = beside the .weights)
  std::string segmenter = "grabcut", sam_encoder, sam_decoder;
  tracking::DynamicMaskerOptions masker;  // SORT, detect_every, refinement, the motion cue's options (run config's dynamic:)
  bool motion_cue = false;  // --mask detector: the motion cue's boxes beside the detector's (--motion-cue)
};

// Whether the motion cue prompts the masks: --mask motion, or --mask detector --motion-cue.
inline bool usesMotionCue(const MaskingOptions& o) {
  return o.source == MaskSource::kMotion || (o.source == MaskSource::kDetector && o.motion_cue);
}

class MaskingStage {
 public:
  // Loads the segmenter (errors name the files). T_B_C: its rotation turns gyro rotations into
  // camera rotations.
  MaskingStage(const MaskingOptions& options, const data::CameraModel& camera, const Eigen::Isometry3d& T_B_C);
  ~MaskingStage();

  // Until `in` is drained or `out` closed; then closes `out`. biases: nullptr without an
  // estimator. Exceptions propagate.
  void run(Channel<PipelineFrame>& in, Channel<PipelineFrame>& out, EstimatorFeedback* biases);

  // The frame-to-frame gap at which this stage's bias is taken (frame k uses the bias after k - 3).
  static constexpr int kBiasDelay = 3;

 private:
  // False when the estimator stopped before the bias this frame needs.
  bool process(PipelineFrame* frame, EstimatorFeedback* biases);

  MaskingOptions options_;
  data::CameraModel camera_;
  Eigen::Isometry3d T_B_C_;
  Eigen::Matrix3d R_B_C_;
  std::unique_ptr<tracking::DynamicMasker> masker_;
  std::unique_ptr<tracking::MotionCue> motion_;
  tracking::ObjectMotionClassifier object_motion_;  // with the cue: which tracked objects stay still
  vio::GyroRotationPredictor gyro_;
  vio::ImuStatePredictor imu_;        // with the cue: the estimator's state carried to this frame
  std::deque<int64_t> recent_frames_;  // stamps of the last kBiasDelay + 1 frames (what imu_ keeps)
  // The movers' boxes per frame number (1-based, as in the MOT file) and the frame number of each
  // exact mask's file name (the files in name order, one per frame).
  std::map<int, std::vector<data::MotBox>> objects_;
  std::map<std::string, int> frame_of_mask_;
  int64_t previous_t_ = -1;
};

}  // namespace adugs::app
