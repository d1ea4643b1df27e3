#include "app/pipeline/masking_stage.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "data/elapsed_time.h"
#include "data/input_error.h"
#include "data/sources/ground_truth_mask.h"
#include "tracking/eval/mask_overlap.h"
#include "tracking/segment/segmenter_factory.h"

namespace adugs::app {

MaskingStage::MaskingStage(const MaskingOptions& options, const data::CameraModel& camera,
                           const Eigen::Isometry3d& T_B_C)
    : options_(options), camera_(camera), T_B_C_(T_B_C), R_B_C_(T_B_C.rotation()) {
  if (options_.source == MaskSource::kGroundTruth && options_.mask_dir.empty())
    throw data::InputError("--mask", 0, "mask",
                           "--mask gt needs the simulator's mav0/mask0/data folder, which this sequence does not have");
  if (options_.source == MaskSource::kDetector) {
    if (options_.detector_model.empty())
      throw data::InputError("--detector-model", 0, "detector_model",
                             "--mask detector needs a detector model (ultralytics .torchscript, .onnx or darknet .weights)");
  }
  if (options_.source == MaskSource::kDetector || options_.source == MaskSource::kMotion)
    masker_ = std::make_unique<tracking::DynamicMasker>(
        options_.masker, tracking::makeBoxSegmenter(options_.segmenter, options_.sam_encoder, options_.sam_decoder,
                                                       options_.masker.grabcut));
  if (usesMotionCue(options_)) {
    motion_ = std::make_unique<tracking::MotionCue>(camera_, options_.masker.motion_cue);
    object_motion_ = tracking::ObjectMotionClassifier(options_.masker.object_motion, camera_);
  }
  if (masker_ && !options_.mask_dir.empty() && !options_.objects_path.empty()) {
    objects_ = data::readMotFile(options_.objects_path);
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(options_.mask_dir))
      if (entry.is_regular_file()) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    for (size_t k = 0; k < names.size(); ++k) frame_of_mask_[names[k]] = static_cast<int>(k) + 1;
  }
}

MaskingStage::~MaskingStage() = default;

bool MaskingStage::process(PipelineFrame* f, EstimatorFeedback* biases) {
  const data::Frame& frame = f->frame;
  if (options_.source == MaskSource::kGroundTruth) {
    f->mask = data::loadGroundTruthMask(options_.mask_dir, frame);
    return true;
  }
  if (!masker_) return true;
  const int64_t previous_t = previous_t_;
  previous_t_ = frame.t_ns;
  const bool compensate = options_.masker.camera_motion_compensation;
  if (compensate || motion_) {
    for (const data::ImuSample& s : f->imu) gyro_.addImu(s);
  }
  if (motion_) {
    for (const data::ImuSample& s : f->imu) imu_.addImu(s);
    recent_frames_.push_back(frame.t_ns);
    if (recent_frames_.size() > static_cast<size_t>(kBiasDelay) + 1) recent_frames_.pop_front();
  }
  // The gyro's rotation since the previous frame (the identity without an IMU), and for the
  // motion cue the camera's mean velocity since then, in this frame's camera axes.
  Eigen::Matrix3d R_Ccur_Cprev = Eigen::Matrix3d::Identity();
  std::optional<Eigen::Vector3d> v_C;
  const double dt_s = previous_t >= 0 ? (frame.t_ns - previous_t) * 1e-9 : 0.0;
  if ((compensate || motion_) && previous_t >= 0) {
    EstimatorFeedback::AfterFrame after;
    if (biases && !biases->waitFor(f->index - kBiasDelay, &after)) return false;
    R_Ccur_Cprev = gyro_.cameraRotation(previous_t, frame.t_ns, after.gyro_bias, R_B_C_).transpose();
    if (motion_ && after.state && dt_s > 0) {
      // The stamps on the IMU clock the state's (camera stamp + the estimator's time offset).
      const int64_t offset = after.state->t_ns - after.frame_t_ns;
      const vio::NavState at_previous = imu_.predict(*after.state, previous_t + offset);
      const vio::NavState now = imu_.predict(at_previous, frame.t_ns + offset);
      v_C = vio::cameraDisplacement(at_previous, now, T_B_C_) / dt_s;
    }
  }
  // What the next frames' predictions start from: the state after frame k + 1 - kBiasDelay, whose
  // camera stamp is the oldest kept; half a second for the time offset.
  if (motion_) imu_.dropBefore(recent_frames_.front() - 500'000'000);
  if (compensate && previous_t >= 0) {
    // The rotation moves every static pixel; SORT removes it.
    masker_->compensateCameraMotion([&](const Eigen::Vector2d& p) -> Eigen::Vector2d {
      const Eigen::Vector3d ray = R_Ccur_Cprev * camera_.unproject(p);
      if (ray.z() < 1e-3) return p;
      return camera_.normalizedToPixel(ray.head<2>() / ray.z());
    });
  }
  gyro_.dropBefore(frame.t_ns);
  // The detection stage decided which frames get detections (tracking::isDetectionFrame).
  const auto t0 = std::chrono::steady_clock::now();
  const cv::Mat& image = frame.colour.empty() ? frame.image : frame.colour;
  std::vector<tracking::Detection> prompts;
  std::vector<tracking::PointPrompt> points;
  if (motion_) {
    prompts = motion_->detect(frame.image, R_Ccur_Cprev, v_C, dt_s);
    masker_->setStaticObjects(object_motion_.staticIds());  // judged up to the previous frame
    points = tracking::cuePointPrompts(motion_->points());
  }
  if (f->detections) prompts.insert(prompts.end(), f->detections->begin(), f->detections->end());
  const tracking::DynamicMaskResult r =
      f->detections || motion_ ? masker_->process(image, prompts, points) : masker_->carry(image);
  if (motion_) {
    object_motion_.update(r.objects, motion_->points(), motion_->translating());
    f->objects_seen_static = object_motion_.everStatic();
  }
  f->mask_ms = data::msSince(t0);
  f->mask = r.mask;
  f->masked_fraction = r.masked_fraction;
  f->objects = r.objects;
  if (!options_.mask_dir.empty()) {
    const cv::Mat exact = loadGroundTruthMask(options_.mask_dir, frame);
    const tracking::MaskOverlap whole = tracking::maskOverlap(exact, r.mask);
    f->exact_pixels = static_cast<double>(whole.exact);
    f->exact_covered = static_cast<double>(whole.covered);
    f->masked_pixels = static_cast<double>(whole.masked);
    // Per mover class: the exact pixels inside the class's boxes (a pixel in boxes of two classes
    // counts for both).
    const auto frame_number = frame_of_mask_.find(std::filesystem::path(frame.path).filename().string());
    const auto boxes = frame_number == frame_of_mask_.end() ? objects_.end() : objects_.find(frame_number->second);
    if (boxes != objects_.end()) {
      std::map<int, std::vector<cv::Rect>> by_class;
      for (const data::MotBox& b : boxes->second) {
        if (b.confidence == 0) continue;  // the simulator's standing objects (MOT's "ignore"): no movers
        by_class[b.class_id].emplace_back(cv::Point(static_cast<int>(b.left), static_cast<int>(b.top)),
                                          cv::Size(static_cast<int>(b.width), static_cast<int>(b.height)));
      }
      for (const auto& [cls, rects] : by_class) {
        const tracking::MaskOverlap o = tracking::maskOverlapInBoxes(exact, r.mask, rects);
        f->exact_by_class[cls] = {static_cast<double>(o.exact), static_cast<double>(o.covered)};
      }
    }
    if (motion_ && f->detections) {
      // Both cues prompt the one mask: each cue is credited with the mask inside its boxes.
      std::vector<cv::Rect> motion_boxes, detector_boxes;
      for (const tracking::TrackedObject& o : r.objects)
        (o.class_id == tracking::kMovingClass ? motion_boxes : detector_boxes).push_back(cv::Rect(o.box.rect()));
      const tracking::MaskOverlap by_motion = tracking::maskOverlapInBoxes(exact, r.mask, motion_boxes);
      const tracking::MaskOverlap by_detector = tracking::maskOverlapInBoxes(exact, r.mask, detector_boxes);
      f->masked_motion = static_cast<double>(by_motion.masked);
      f->exact_covered_motion = static_cast<double>(by_motion.covered);
      f->masked_detector = static_cast<double>(by_detector.masked);
      f->exact_covered_detector = static_cast<double>(by_detector.covered);
    }
  }
  return true;
}

void MaskingStage::run(Channel<PipelineFrame>& in, Channel<PipelineFrame>& out, EstimatorFeedback* biases) {
  PipelineFrame f;
  while (in.pop(&f)) {
    if (!process(&f, biases)) break;
    if (!out.push(std::move(f))) break;
  }
  out.close();
}

}  // namespace adugs::app
