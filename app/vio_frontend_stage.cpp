#include "app/vio_frontend_stage.h"

#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "data/input_error.h"
#include "tracking/dynamic_masker.h"
#include "tracking/segmenter_factory.h"
#include "tracking/detector_factory.h"

namespace adugs::app {
namespace {
namespace fs = std::filesystem;

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The simulator's ground-truth mask of a frame: mav0/mask0/data/<image file name>.
cv::Mat loadGroundTruthMask(const std::string& mask_dir, const data::Frame& frame) {
  const std::string path = (fs::path(mask_dir) / fs::path(frame.path).filename()).string();
  cv::Mat mask = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (mask.empty())
    throw data::InputError(path, 0, "mask", "missing or unreadable dynamic mask (--mask gt)");
  if (mask.size() != frame.image.size())
    throw data::InputError(
        path, 0, "mask",
        "mask is " + std::to_string(mask.cols) + "x" + std::to_string(mask.rows) + ", the image " +
            std::to_string(frame.image.cols) + "x" + std::to_string(frame.image.rows));
  return mask;
}

}  // namespace

FrontEndStage::FrontEndStage(data::SequenceSource& source,
                             const vio::FeatureTrackerOptions& tracker_options,
                             const data::CameraModel& camera, const Eigen::Isometry3d& T_B_C,
                             const FrontEndStageOptions& options)
    : source_(source),
      tracker_(tracker_options, camera),
      R_B_C_(T_B_C.rotation()),
      options_(options),
      camera_(camera) {
  if (options_.mask == "gt" && options_.mask_dir.empty())
    throw data::InputError("--mask", 0, "mask",
                           "--mask gt needs the simulator's mav0/mask0/data folder, which this "
                           "sequence does not have");
  // The dynamic-object stage of the paper: detector -> SORT -> box segmentation -> refinement.
  if (options_.mask == "detector") {
    if (options_.detector_model.empty())
      throw data::InputError("--detector-model", 0, "detector_model",
                             "--mask detector needs a detector model (ultralytics .torchscript, .onnx or darknet .weights)");
    detector_ = tracking::makeDetector(options_.detector_model, options_.detector_config);
    masker_ = std::make_unique<tracking::DynamicMasker>(
        options_.masker,
        tracking::makeBoxSegmenter(options_.segmenter, options_.sam_encoder, options_.sam_decoder));
  }
  if (!options_.overlay_path.empty()) overlay_ = std::make_unique<OverlayVideo>(options_.overlay_path, 20.0);
}

FrontEndStage::~FrontEndStage() = default;

cv::Mat FrontEndStage::makeMask(const data::Frame& frame, int64_t previous_t, TrackedFrame* out) {
  if (options_.mask == "gt") return loadGroundTruthMask(options_.mask_dir, frame);
  if (!masker_) return {};
  const auto t0 = std::chrono::steady_clock::now();
  if (options_.masker.camera_motion_compensation && previous_t >= 0) {
    // The gyro's rotation since the previous frame moves every static pixel; SORT removes it.
    const Eigen::Matrix3d R_Ccur_Cprev =
        (R_B_C_.transpose() * gyro_.rotation(previous_t, frame.t_ns, last_gyro_bias_).toRotationMatrix() * R_B_C_)
            .transpose();
    masker_->compensateCameraMotion([&](const Eigen::Vector2d& p) -> Eigen::Vector2d {
      const Eigen::Vector3d f = R_Ccur_Cprev * camera_.unproject(p);
      if (f.z() < 1e-3) return p;
      return camera_.normalizedToPixel(f.head<2>() / f.z());
    });
  }
  const tracking::DynamicMaskResult r = masker_->detectionDue()
                                            ? masker_->process(frame.image, detector_->detect(frame.image))
                                            : masker_->carry(frame.image);
  out->mask_ms = msSince(t0);
  out->masked_fraction = r.masked_fraction;
  last_objects_ = r.objects;
  if (!options_.mask_dir.empty()) {
    const cv::Mat exact = loadGroundTruthMask(options_.mask_dir, frame);
    out->exact_pixels = cv::countNonZero(exact);
    out->exact_covered = cv::countNonZero(exact & r.mask);
    out->masked_pixels = cv::countNonZero(r.mask);
  }
  return r.mask;
}

void FrontEndStage::writeOverlay(const data::Frame& frame, const cv::Mat& mask, const TrackedFrame& out) {
  if (!overlay_) return;
  OverlayContent c;
  c.mask = mask;
  c.objects = last_objects_;
  c.kept = out.features.pixels;
  c.dropped = tracker_.lastDroppedDynamic();
  const double masked = mask.empty() ? 0.0 : static_cast<double>(cv::countNonZero(mask)) / static_cast<double>(mask.total());
  char status[160];
  std::snprintf(status, sizeof status, "t %.2f s | features %zu kept, %d dropped as dynamic | masked %.1f %% | %zu objects",
                out.sequence_s, out.features.size(), out.dropped_dynamic, 100.0 * masked, last_objects_.size());
  c.status = status;
  overlay_->write(drawOverlay(frame.image, c));
}

void FrontEndStage::run(Channel<TrackedFrame>& frames, Channel<Eigen::Vector3d>& gyro_biases) {
  data::Measurement m;
  int64_t previous_frame_t = -1;
  int frame_index = 0;
  TrackedFrame out;
  while (source_.next(m)) {
    if (first_t_ < 0) first_t_ = m.timeNs();
    if (m.isImu()) {
      ++imu_samples_;
      gyro_.addImu(m.imu);
      out.imu.push_back(m.imu);
      continue;
    }
    out.sequence_s = data::nsToSec(m.frame.t_ns - first_t_);
    const cv::Mat mask = makeMask(m.frame, previous_frame_t, &out);

    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
    if (frame_index >= 2 && !gyro_biases.pop(&gyro_bias)) break;  // the estimator stopped
    last_gyro_bias_ = gyro_bias;
    if (previous_frame_t >= 0) {
      const Eigen::Matrix3d R_B =
          gyro_.rotation(previous_frame_t, m.frame.t_ns, gyro_bias).toRotationMatrix();
      tracker_.setPredictedRotation(R_B_C_.transpose() * R_B * R_B_C_);
      gyro_.dropBefore(m.frame.t_ns);
    }
    const auto t0 = std::chrono::steady_clock::now();
    out.features = tracker_.trackFrame(m.frame.t_ns, m.frame.image, mask);
    out.frontend_ms = msSince(t0);
    out.dropped_dynamic = tracker_.lastStats().dropped_dynamic;
    writeOverlay(m.frame, mask, out);
    if (!frames.push(std::move(out))) break;
    out = TrackedFrame{};
    previous_frame_t = m.frame.t_ns;
    ++frame_index;
  }
  frames.close();
}

}  // namespace adugs::app
