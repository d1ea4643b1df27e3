#pragma once
// One camera frame on its way through the pipeline (app/pipeline/pipeline.h). Each stage fills its
// part and moves the frame on to the next.
#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "data/sources/sequence_source.h"
#include "data/types.h"
#include "tracking/detect/detector.h"
#include "tracking/sort/sort_tracker.h"
#include "vio/frontend/feature_tracker.h"

namespace adugs::app {

struct PipelineFrame {
  // Acquisition (app/pipeline/frame_gate.h)
  int index = 0;  // among the frames that entered the pipeline: 0, 1, 2, ... (dropped ones not counted)
  data::Frame frame;
  std::vector<data::ImuSample> imu;  // every sample since the previous frame that entered, in time order
  double sequence_s = 0;             // since the source's first measurement
  std::chrono::steady_clock::time_point acquired_at;  // when the source handed the frame over

  // Detection (app/pipeline/detection_stage.h): set on the frames the detector ran on
  std::optional<std::vector<tracking::Detection>> detections;
  double detect_ms = 0;

  // Masking (app/pipeline/masking_stage.h)
  cv::Mat mask;  // CV_8UC1, 255 = dynamic; empty = no mask
  std::vector<tracking::TrackedObject> objects;  // the masker's boxes
  double mask_ms = -1;  // SORT + segmentation + refinement; < 0: no detector mask computed
  double masked_fraction = 0;
  // Detector masks scored against the simulator's exact masks (when the sequence has them):
  // pixels of the exact mask, of those covered, and masked in all.
  double exact_pixels = 0, exact_covered = 0, masked_pixels = 0;
  // With both cues (--mask detector --motion-cue): the same, of the mask inside each cue's boxes
  // (the motion cue's: class tracking::kMovingClass; the detector's: every other class).
  double exact_covered_motion = 0, masked_motion = 0, exact_covered_detector = 0, masked_detector = 0;
  // Per mover class (COCO id, from the simulator's objects0/gt.txt): exact pixels inside the
  // class's boxes, and of those the masked ones.
  std::map<int, std::pair<double, double>> exact_by_class;
  size_t objects_seen_static = 0;  // with the motion cue: tracked objects judged static so far (not masked)

  // Front-end (app/pipeline/frontend_stage.h)
  vio::FrameFeatures features;
  std::vector<cv::Point2f> dropped_points;  // features dropped as dynamic, pixels in this image
  int dropped_dynamic = 0;
  double frontend_ms = 0;

  // Estimator (app/pipeline/estimator_stage.h)
  std::optional<data::StampedPose> pose;  // T_W_B at the frame, once initialised
  double backend_ms = 0;
};

}  // namespace adugs::app
