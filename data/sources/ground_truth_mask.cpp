#include "data/sources/ground_truth_mask.h"

#include <filesystem>

#include "data/formats/image_file.h"
#include "data/input_error.h"

namespace adugs::data {
namespace fs = std::filesystem;

cv::Mat loadGroundTruthMask(const std::string& mask_dir, const Frame& frame) {
  const std::string path = (fs::path(mask_dir) / fs::path(frame.path).filename()).string();
  cv::Mat mask;
  try {
    mask = readImageFile(path, ImageRead::kGrey);
  } catch (const InputError& e) {
    throw InputError(path, 0, "mask", std::string("missing or unreadable dynamic mask (--mask gt): ") + e.what());
  }
  if (mask.size() != frame.image.size())
    throw data::InputError(path, 0, "mask",
                           "mask is " + std::to_string(mask.cols) + "x" + std::to_string(mask.rows) + ", the image " +
                               std::to_string(frame.image.cols) + "x" + std::to_string(frame.image.rows));
  return mask;
}

}  // namespace adugs::data
