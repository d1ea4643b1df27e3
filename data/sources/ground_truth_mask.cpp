#include "data/sources/ground_truth_mask.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "data/input_error.h"

namespace adugs::data {
namespace fs = std::filesystem;

cv::Mat loadGroundTruthMask(const std::string& mask_dir, const Frame& frame) {
  const std::string path = (fs::path(mask_dir) / fs::path(frame.path).filename()).string();
  cv::Mat mask = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (mask.empty()) throw data::InputError(path, 0, "mask", "missing or unreadable dynamic mask (--mask gt)");
  if (mask.size() != frame.image.size())
    throw data::InputError(path, 0, "mask",
                           "mask is " + std::to_string(mask.cols) + "x" + std::to_string(mask.rows) + ", the image " +
                               std::to_string(frame.image.cols) + "x" + std::to_string(frame.image.rows));
  return mask;
}

}  // namespace adugs::data
