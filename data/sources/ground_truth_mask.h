#pragma once
// The simulator's ground-truth dynamic mask of a frame (`adugs run --mask gt`): the PNG of the same
// file name in the sequence's mav0/mask0/data folder, 255 = a moving object.
#include <opencv2/core.hpp>
#include <string>

#include "data/sources/sequence_source.h"

namespace adugs::data {

// InputError naming the file when it is missing, unreadable or not the image's size.
cv::Mat loadGroundTruthMask(const std::string& mask_dir, const Frame& frame);

}  // namespace adugs::data
