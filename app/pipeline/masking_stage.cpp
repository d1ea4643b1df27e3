#include "app/pipeline/masking_stage.h"

#include <chrono>
#include <filesystem>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "data/input_error.h"
#include "tracking/segmenter_factory.h"

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
  if (mask.empty()) throw data::InputError(path, 0, "mask", "missing or unreadable dynamic mask (--mask gt)");
  if (mask.size() != frame.image.size())
    throw data::InputError(path, 0, "mask",
                           "mask is " + std::to_string(mask.cols) + "x" + std::to_string(mask.rows) + ", the image " +
                               std::to_string(frame.image.cols) + "x" + std::to_string(frame.image.rows));
  return mask;
}

}  // namespace

MaskingStage::MaskingStage(const MaskingOptions& options, const data::CameraModel& camera,
                           const Eigen::Isometry3d& T_B_C)
    : options_(options), camera_(camera), R_B_C_(T_B_C.rotation()) {
  if (options_.mask == "gt" && options_.mask_dir.empty())
    throw data::InputError("--mask", 0, "mask",
                           "--mask gt needs the simulator's mav0/mask0/data folder, which this sequence does not have");
  if (options_.mask == "detector") {
    if (options_.detector_model.empty())
      throw data::InputError("--detector-model", 0, "detector_model",
                             "--mask detector needs a detector model (ultralytics .torchscript, .onnx or darknet .weights)");
    masker_ = std::make_unique<tracking::DynamicMasker>(
        options_.masker, tracking::makeBoxSegmenter(options_.segmenter, options_.sam_encoder, options_.sam_decoder));
  }
}

MaskingStage::~MaskingStage() = default;

bool MaskingStage::process(PipelineFrame* f, BiasFeedback* biases) {
  const data::Frame& frame = f->frame;
  if (options_.mask == "gt") {
    f->mask = loadGroundTruthMask(options_.mask_dir, frame);
    return true;
  }
  if (!masker_) return true;
  const int64_t previous_t = previous_t_;
  previous_t_ = frame.t_ns;
  if (options_.masker.camera_motion_compensation) {
    for (const data::ImuSample& s : f->imu) gyro_.addImu(s);
  }
  if (options_.masker.camera_motion_compensation && previous_t >= 0) {
    // The gyro's rotation since the previous frame moves every static pixel; SORT removes it.
    Eigen::Vector3d bias = Eigen::Vector3d::Zero();
    if (biases && !biases->waitFor(f->index - kBiasDelay, &bias)) return false;
    const Eigen::Matrix3d R_Ccur_Cprev =
        (R_B_C_.transpose() * gyro_.rotation(previous_t, frame.t_ns, bias).toRotationMatrix() * R_B_C_).transpose();
    masker_->compensateCameraMotion([&](const Eigen::Vector2d& p) -> Eigen::Vector2d {
      const Eigen::Vector3d ray = R_Ccur_Cprev * camera_.unproject(p);
      if (ray.z() < 1e-3) return p;
      return camera_.normalizedToPixel(ray.head<2>() / ray.z());
    });
  }
  gyro_.dropBefore(frame.t_ns);
  // The detection stage ran the detector on the frames the masker is due for; one rule, checked.
  if (masker_->detectionDue() != f->detections.has_value())
    throw std::logic_error("frame " + std::to_string(f->index) + ": the detection stage and the masker disagree on detect_every");
  const auto t0 = std::chrono::steady_clock::now();
  const cv::Mat& image = frame.colour.empty() ? frame.image : frame.colour;
  const tracking::DynamicMaskResult r = f->detections ? masker_->process(image, *f->detections) : masker_->carry(image);
  f->mask_ms = msSince(t0);
  f->mask = r.mask;
  f->masked_fraction = r.masked_fraction;
  f->objects = r.objects;
  if (!options_.mask_dir.empty()) {
    const cv::Mat exact = loadGroundTruthMask(options_.mask_dir, frame);
    f->exact_pixels = cv::countNonZero(exact);
    f->exact_covered = cv::countNonZero(exact & r.mask);
    f->masked_pixels = cv::countNonZero(r.mask);
  }
  return true;
}

void MaskingStage::run(Channel<PipelineFrame>& in, Channel<PipelineFrame>& out, BiasFeedback* biases) {
  PipelineFrame f;
  while (in.pop(&f)) {
    if (!process(&f, biases)) break;
    if (!out.push(std::move(f))) break;
  }
  out.close();
}

}  // namespace adugs::app
