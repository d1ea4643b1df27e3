#include "tracking/detect/darknet_detector.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgproc.hpp>

#include "data/input_error.h"

namespace adugs::tracking {
namespace {

// width= and height= of the cfg's [net] section.
cv::Size networkInputSize(const std::string& cfg_path) {
  std::ifstream in(cfg_path);
  std::string line, section;
  int width = 0, height = 0;
  while (std::getline(in, line)) {
    line.erase(std::remove_if(line.begin(), line.end(), ::isspace), line.end());
    if (line.empty() || line[0] == '#' || line[0] == ';') continue;
    if (line[0] == '[') {
      section = line;
      continue;
    }
    if (section != "[net]" && section != "[network]") continue;
    try {
      if (line.rfind("width=", 0) == 0) width = std::stoi(line.substr(6));
      if (line.rfind("height=", 0) == 0) height = std::stoi(line.substr(7));
    } catch (const std::exception&) {
      throw data::InputError(cfg_path, 0, "[net]", "width/height is not a number: '" + line + "'");
    }
  }
  if (width <= 0 || height <= 0)
    throw data::InputError(cfg_path, 0, "[net]", "no positive width and height in the [net] section");
  return {width, height};
}

void requireFile(const std::string& path, const std::string& what) {
  if (!std::filesystem::is_regular_file(path)) throw data::InputError(path, 0, "model", what + " not found");
}

}  // namespace

std::vector<Detection> decodeDarknetOutput(const cv::Mat& rows, const cv::Size& image_size,
                                           const DarknetOptions& options) {
  std::vector<Detection> out;
  const int classes = rows.cols - 5;
  for (int r = 0; r < rows.rows; ++r) {
    const float* a = rows.ptr<float>(r);
    const float* cls = a + 5;
    const int best = static_cast<int>(std::max_element(cls, cls + classes) - cls);
    if (cls[best] < options.score_threshold || !options.keep_classes.count(best)) continue;
    Detection d;
    d.box = {a[0] * image_size.width, a[1] * image_size.height, a[2] * image_size.width, a[3] * image_size.height};
    d.class_id = best;
    d.score = cls[best];
    out.push_back(d);
  }
  return out;
}

DarknetDetector::DarknetDetector(const std::string& cfg_path, const std::string& weights_path,
                                 const DarknetOptions& options)
    : options_(options) {
  requireFile(cfg_path, "darknet .cfg file");
  requireFile(weights_path, "darknet .weights file");
  input_size_ = networkInputSize(cfg_path);
  try {
    net_ = cv::dnn::readNetFromDarknet(cfg_path, weights_path);
  } catch (const cv::Exception& e) {
    throw data::InputError(weights_path, 0, "model", std::string("OpenCV dnn cannot load it with ") + cfg_path +
                                                         ": " + e.what());
  }
  if (net_.empty()) throw data::InputError(weights_path, 0, "model", "OpenCV dnn loaded an empty network");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  outputs_ = net_.getUnconnectedOutLayersNames();
}

std::vector<Detection> DarknetDetector::detect(const cv::Mat& image) {
  cv::Mat bgr = image;
  if (image.channels() == 1) cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  net_.setInput(cv::dnn::blobFromImage(bgr, 1.0 / 255.0, input_size_, cv::Scalar(), true, false, CV_32F));
  std::vector<cv::Mat> outs;
  net_.forward(outs, outputs_);
  std::vector<Detection> candidates;
  for (const cv::Mat& o : outs) {
    if (o.dims != 2 || o.cols < 6)
      throw data::InputError("darknet model", 0, "output", "not a [yolo] output (rows x (5 + classes))");
    const std::vector<Detection> part = decodeDarknetOutput(o, bgr.size(), options_);
    candidates.insert(candidates.end(), part.begin(), part.end());
  }
  return suppressOverlaps(candidates, options_.score_threshold, options_.nms_iou);
}

}  // namespace adugs::tracking
