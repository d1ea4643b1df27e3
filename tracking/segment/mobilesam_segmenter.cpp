#include "tracking/segment/mobilesam_segmenter.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "data/input_error.h"
#include "tracking/segment/sam_transforms.h"
#include "tracking/torchscript_module.h"

namespace adugs::tracking {
namespace {

constexpr const char* kEncoderWhat = "SAM image encoder TorchScript (scripts/export_mobilesam.py)";
constexpr const char* kDecoderWhat = "SAM prompt decoder TorchScript (scripts/export_mobilesam.py)";

bool hasShape(const at::Tensor& t, std::initializer_list<int64_t> dims) {
  return t.defined() && t.sizes() == c10::IntArrayRef(dims);
}

}  // namespace

struct MobileSamSegmenter::Models {
  torch::jit::Module encoder;
  torch::jit::Module decoder;

  at::Tensor encode(const cv::Mat& image, const std::string& path) {
    cv::Mat blob = samEncoderInput(image);
    const at::Tensor input = torch::from_blob(blob.ptr<float>(), {1, 3, kSamImageSize, kSamImageSize});
    const c10::IValue out = runForward(encoder, {input}, path);
    const at::Tensor embeddings = out.isTensor() ? out.toTensor() : at::Tensor();
    if (!hasShape(embeddings, {1, kSamEmbeddingDim, kSamEmbeddingSize, kSamEmbeddingSize}))
      throw data::InputError(path, 0, "output",
                             "not a SAM image encoder: expected embeddings [1, 256, 64, 64], it returns " +
                                 (embeddings.defined() ? shapeOf(embeddings) : std::string("no tensor")));
    return embeddings.to(torch::kFloat);
  }

  // Mask logits of the whole image (CV_32F) for one box prompt.
  cv::Mat decode(const at::Tensor& embeddings, const Box& box, cv::Size image_size, const std::string& path) {
    const cv::Vec4f corners = samBoxPrompt(box, image_size);
    const at::Tensor coords = torch::tensor({corners[0], corners[1], corners[2], corners[3]}).reshape({1, 2, 2});
    const at::Tensor labels = torch::tensor({2.0f, 3.0f}).reshape({1, 2});  // box top-left, bottom-right
    const c10::IValue out = runForward(decoder, {embeddings, coords, labels}, path);
    at::Tensor low_res;
    if (out.isTuple() && out.toTupleRef().elements().size() >= 2 && out.toTupleRef().elements()[0].isTensor())
      low_res = out.toTupleRef().elements()[0].toTensor();
    if (!hasShape(low_res, {1, 1, kSamLowResMaskSize, kSamLowResMaskSize}))
      throw data::InputError(path, 0, "output",
                             "not a SAM prompt decoder: expected (low_res_masks [1, 1, 256, 256], iou_predictions), "
                             "it returns " +
                                 (low_res.defined() ? shapeOf(low_res) + " first" : std::string("something else")));
    low_res = low_res.to(torch::kFloat).contiguous();
    const cv::Mat logits(kSamLowResMaskSize, kSamLowResMaskSize, CV_32F, low_res.data_ptr<float>());
    return samUpscaleLowResMask(logits, image_size);
  }
};

MobileSamSegmenter::MobileSamSegmenter(const std::string& encoder_path, const std::string& decoder_path,
                                       const MobileSamOptions& options)
    : models_(std::make_unique<Models>()),
      encoder_path_(encoder_path),
      decoder_path_(decoder_path),
      options_(options) {
  models_->encoder = loadTorchScript(encoder_path, kEncoderWhat);
  requireForwardInputs(models_->encoder, {"image"}, encoder_path, kEncoderWhat);
  models_->decoder = loadTorchScript(decoder_path, kDecoderWhat);
  requireForwardInputs(models_->decoder, {"image_embeddings", "point_coords", "point_labels"}, decoder_path,
                       kDecoderWhat);
  // The decoder is cheap (the encoder costs seconds): one dry run checks its outputs now.
  models_->decode(torch::zeros({1, kSamEmbeddingDim, kSamEmbeddingSize, kSamEmbeddingSize}),
                  Box::fromCorners(8, 8, 40, 40), {64, 48}, decoder_path);
}

MobileSamSegmenter::~MobileSamSegmenter() = default;

cv::Mat MobileSamSegmenter::segment(const cv::Mat& image, const std::vector<Box>& boxes) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw std::invalid_argument("MobileSamSegmenter: image must be 8-bit grey or BGR");
  fallbacks_ = 0;
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
  at::Tensor embeddings;  // computed lazily: frames without boxes skip the encoder
  for (const Box& b : boxes) {
    const cv::Rect r = clippedRect(b, image.cols, image.rows);
    if (r.empty()) continue;
    if (!embeddings.defined()) embeddings = models_->encode(image, encoder_path_);
    // Prompt with the box clipped to the image, as the mask is limited to it.
    const Box clipped = Box::fromCorners(std::max(0.0, b.left()), std::max(0.0, b.top()),
                                         std::min<double>(image.cols, b.right()),
                                         std::min<double>(image.rows, b.bottom()));
    const cv::Mat logits = models_->decode(embeddings, clipped, image.size(), decoder_path_);
    cv::Mat object = logits(r) > 0;
    if (cv::countNonZero(object) < options_.min_foreground_fraction * r.area()) {
      object.setTo(255);
      ++fallbacks_;
    }
    cv::Mat target = mask(r);
    cv::bitwise_or(target, object, target);
  }
  return mask;
}

}  // namespace adugs::tracking
