#include "tracking/mobilesam_segmenter.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "data/input_error.h"
#include "tracking/onnx_signature.h"
#include "tracking/sam_transforms.h"

namespace adugs::tracking {
namespace {

constexpr int64_t kAny = -1;
const char* const kEmbeddings = "image_embeddings";
const std::vector<std::string> kDecoderOutputs = {"masks", "iou_predictions", "low_res_masks"};

struct ExpectedTensor {
  std::string name;
  std::vector<int64_t> dims;  // kAny matches anything
};

std::string describe(const ExpectedTensor& e) {
  std::string s = e.name + " [";
  for (size_t i = 0; i < e.dims.size(); ++i)
    s += (i ? ", " : "") + (e.dims[i] == kAny ? std::string("N") : std::to_string(e.dims[i]));
  return s + "]";
}

std::string describe(const std::vector<OnnxTensorInfo>& tensors) {
  std::string s;
  for (const OnnxTensorInfo& t : tensors)
    s += (s.empty() ? "" : ", ") + t.name + " " + describeShape(t);
  return s;
}

// Symbolic dimensions (dynamic axes) and undeclared shapes are accepted: only fixed
// dimensions that contradict SAM's are errors.
bool shapeMatches(const OnnxTensorInfo& t, const std::vector<int64_t>& dims) {
  if (!t.has_shape) return true;
  if (t.dims.size() != dims.size()) return false;
  for (size_t i = 0; i < dims.size(); ++i)
    if (dims[i] != kAny && t.dims[i] >= 0 && t.dims[i] != dims[i]) return false;
  return true;
}

const OnnxTensorInfo* findTensor(const std::vector<OnnxTensorInfo>& tensors,
                                 const std::string& name) {
  for (const OnnxTensorInfo& t : tensors)
    if (t.name == name) return &t;
  return nullptr;
}

void requireTensors(const std::string& path, const char* field,
                    const std::vector<OnnxTensorInfo>& actual,
                    const std::vector<ExpectedTensor>& expected, const char* what) {
  for (const ExpectedTensor& e : expected) {
    const OnnxTensorInfo* t = findTensor(actual, e.name);
    if (t && shapeMatches(*t, e.dims)) continue;
    std::string list;
    for (const ExpectedTensor& x : expected) list += (list.empty() ? "" : ", ") + describe(x);
    throw data::InputError(path, 0, field,
                           std::string("not a ") + what + ": expected " + list + "; " +
                               (t ? "'" + e.name + "' has shape " + describeShape(*t)
                                  : "'" + e.name + "' is missing") +
                               " (the graph has " + describe(actual) + ")");
  }
}

// The encoder may name its single image input freely ("x" in SAM's export, "images"...).
std::string checkEncoder(const std::string& path, const OnnxSignature& sig) {
  const std::vector<int64_t> image_dims = {kAny, 3, kSamImageSize, kSamImageSize};
  if (sig.inputs.size() != 1 || !shapeMatches(sig.inputs[0], image_dims))
    throw data::InputError(path, 0, "inputs",
                           "not a SAM image encoder: expected one input [1, 3, 1024, 1024], the "
                           "graph has " +
                               describe(sig.inputs));
  requireTensors(path, "outputs", sig.outputs,
                 {{kEmbeddings, {kAny, kSamEmbeddingDim, kSamEmbeddingSize, kSamEmbeddingSize}}},
                 "SAM image encoder");
  return sig.inputs[0].name;
}

void checkDecoder(const std::string& path, const OnnxSignature& sig) {
  const int64_t low = kSamLowResMaskSize;
  requireTensors(path, "inputs", sig.inputs,
                 {{kEmbeddings, {1, kSamEmbeddingDim, kSamEmbeddingSize, kSamEmbeddingSize}},
                  {"point_coords", {1, kAny, 2}},
                  {"point_labels", {1, kAny}},
                  {"mask_input", {1, 1, low, low}},
                  {"has_mask_input", {1}},
                  {"orig_im_size", {2}}},
                 "SAM prompt decoder");
  requireTensors(path, "outputs", sig.outputs,
                 {{"masks", {1, kAny, kAny, kAny}},
                  {"iou_predictions", {1, kAny}},
                  {"low_res_masks", {1, kAny, low, low}}},
                 "SAM prompt decoder");
}

// OpenCV's importer reports "Node [OpType@domain]:(name) parse error: ..." for a node it cannot
// build; pull the op type out so the user learns which op their OpenCV lacks.
std::string failedOpType(const std::string& message) {
  const size_t start = message.find("Node [");
  if (start == std::string::npos) return {};
  const size_t begin = start + 6;
  const size_t end = message.find_first_of("@]", begin);
  return end == std::string::npos ? std::string() : message.substr(begin, end - begin);
}

cv::dnn::Net loadNet(const std::string& path) {
  try {
    cv::dnn::Net net = cv::dnn::readNetFromONNX(path);
    net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
    return net;
  } catch (const cv::Exception& e) {
    const std::string op = failedOpType(e.what());
    throw data::InputError(
        path, 0, op.empty() ? "" : "op " + op,
        "OpenCV " CV_VERSION " dnn cannot import this graph" +
            (op.empty() ? std::string() : " (unsupported or failing op '" + op + "')") + ": " +
            e.what());
  }
}

[[noreturn]] void rethrowRunError(const std::string& path, const cv::Exception& e) {
  const std::string op = failedOpType(e.what());
  throw data::InputError(
      path, 0, op.empty() ? "" : "op " + op,
      std::string("OpenCV " CV_VERSION " dnn failed to run this graph: ") + e.what());
}

cv::Mat plane(const cv::Mat& blob, int index) {
  return cv::Mat(blob.size[2], blob.size[3], CV_32F, const_cast<float*>(blob.ptr<float>(0, index)));
}

}  // namespace

MobileSamSegmenter::MobileSamSegmenter(const std::string& encoder_path,
                                       const std::string& decoder_path,
                                       const MobileSamOptions& options)
    : encoder_path_(encoder_path), decoder_path_(decoder_path), options_(options) {
  if (options_.min_foreground_fraction < 0 || options_.min_foreground_fraction >= 1)
    throw std::invalid_argument("MobileSamSegmenter: min_foreground_fraction must be in [0, 1)");
  encoder_input_ = checkEncoder(encoder_path_, readOnnxSignature(encoder_path_));
  checkDecoder(decoder_path_, readOnnxSignature(decoder_path_));
  encoder_ = loadNet(encoder_path_);
  decoder_ = loadNet(decoder_path_);
  // The decoder is cheap: one dry run surfaces graphs OpenCV imports but cannot run (the real
  // export sizes its output from orig_im_size at run time) now rather than on the first frame.
  const int dims[] = {1, kSamEmbeddingDim, kSamEmbeddingSize, kSamEmbeddingSize};
  decode(cv::Mat(4, dims, CV_32F, cv::Scalar(0)), Box::fromCorners(8, 8, 40, 40), {64, 48});
}

cv::Mat MobileSamSegmenter::encode(const cv::Mat& image) {
  cv::Mat embeddings;
  try {
    encoder_.setInput(samEncoderInput(image), encoder_input_);
    embeddings = encoder_.forward(kEmbeddings);
  } catch (const cv::Exception& e) {
    rethrowRunError(encoder_path_, e);
  }
  const std::vector<int> expected = {1, kSamEmbeddingDim, kSamEmbeddingSize, kSamEmbeddingSize};
  if (embeddings.dims != 4 ||
      std::vector<int>(embeddings.size.p, embeddings.size.p + 4) != expected)
    throw data::InputError(encoder_path_, 0, kEmbeddings,
                           "the encoder output is not 1 x 256 x 64 x 64");
  return embeddings;
}

cv::Mat MobileSamSegmenter::decode(const cv::Mat& embeddings, const Box& box, cv::Size image_size) {
  const cv::Vec4f corners = samBoxPrompt(box, image_size);
  const int coords_dims[] = {1, 2, 2}, labels_dims[] = {1, 2};
  const int mask_dims[] = {1, 1, kSamLowResMaskSize, kSamLowResMaskSize}, one[] = {1}, two[] = {2};
  const float labels[] = {2, 3};  // box top-left, box bottom-right
  const float orig_size[] = {static_cast<float>(image_size.height),
                             static_cast<float>(image_size.width)};
  std::vector<cv::Mat> outputs;
  try {
    decoder_.setInput(embeddings, kEmbeddings);
    decoder_.setInput(cv::Mat(3, coords_dims, CV_32F, const_cast<float*>(corners.val)).clone(),
                      "point_coords");
    decoder_.setInput(cv::Mat(2, labels_dims, CV_32F, const_cast<float*>(labels)).clone(),
                      "point_labels");
    decoder_.setInput(cv::Mat(4, mask_dims, CV_32F, cv::Scalar(0)), "mask_input");
    decoder_.setInput(cv::Mat(1, one, CV_32F, cv::Scalar(0)), "has_mask_input");
    decoder_.setInput(cv::Mat(1, two, CV_32F, const_cast<float*>(orig_size)).clone(),
                      "orig_im_size");
    decoder_.forward(outputs,
                     std::vector<cv::String>(kDecoderOutputs.begin(), kDecoderOutputs.end()));
  } catch (const cv::Exception& e) {
    rethrowRunError(decoder_path_, e);
  }
  const cv::Mat& masks = outputs[0];
  const cv::Mat& scores = outputs[1];
  const cv::Mat& low_res = outputs[2];
  if (masks.dims != 4 || low_res.dims != 4 || low_res.size[1] != masks.size[1] ||
      low_res.size[2] != kSamLowResMaskSize || low_res.size[3] != kSamLowResMaskSize ||
      static_cast<int>(scores.total()) != masks.size[1])
    throw data::InputError(decoder_path_, 0, "outputs",
                           "masks / iou_predictions / low_res_masks do not have SAM's shapes");
  // A multimask export returns 4 masks; for a 2-point (box) prompt SAM's select_masks picks the
  // best-scored of masks 1..3 (mask 0 is meant for multi-point prompts).
  int best = 0;
  if (masks.size[1] > 1) {
    const float* s = scores.ptr<float>();
    best = static_cast<int>(std::max_element(s + 1, s + masks.size[1]) - s);
  }
  // The real export returns masks at orig_im_size; an export with a fixed output size (what
  // OpenCV 4.6 can run) is post-processed here from the low-resolution logits instead.
  if (masks.size[2] == image_size.height && masks.size[3] == image_size.width)
    return plane(masks, best).clone();
  return samUpscaleLowResMask(plane(low_res, best), image_size);
}

cv::Mat MobileSamSegmenter::segment(const cv::Mat& image, const std::vector<Box>& boxes) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw std::invalid_argument("MobileSamSegmenter: image must be 8-bit grey or BGR");
  fallbacks_ = 0;
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
  cv::Mat embeddings;  // computed lazily: frames without boxes skip the encoder
  for (const Box& b : boxes) {
    const cv::Rect r = clippedRect(b, image.cols, image.rows);
    if (r.empty()) continue;
    if (embeddings.empty()) embeddings = encode(image);
    // Prompt with the box clipped to the image, as the mask is limited to it.
    const Box clipped = Box::fromCorners(std::max(0.0, b.left()), std::max(0.0, b.top()),
                                         std::min<double>(image.cols, b.right()),
                                         std::min<double>(image.rows, b.bottom()));
    const cv::Mat logits = decode(embeddings, clipped, image.size());
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
