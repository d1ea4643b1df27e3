#pragma once
// Debug picture of the front-end: the image in BGR, the dynamic mask tinted red, each feature as
// a dot with a line back to its previous position coloured by lifetime (blue = new, through
// green, to red = tracked for `saturate_lifetime` frames or more), dropped dynamic points as
// magenta crosses and rejected outliers as yellow crosses.
#include <opencv2/core.hpp>
#include <vector>

#include "vio/frontend/feature_tracker.h"

namespace adugs::vio {

struct FeatureOverlayStyle {
  int saturate_lifetime = 30;  // frames at which the colour reaches red
  int radius = 3;
  double mask_alpha = 0.35;  // tint strength over dynamic pixels
};

// image: CV_8UC1 or CV_8UC3; mask: empty or CV_8UC1 of the image's size (nonzero = dynamic).
// Returns a new CV_8UC3 image; std::invalid_argument for other types or sizes.
cv::Mat drawFeatureOverlay(const cv::Mat& image, const FrameFeatures& features,
                           const cv::Mat& mask = cv::Mat(),
                           const std::vector<cv::Point2f>& dropped_dynamic = {},
                           const std::vector<cv::Point2f>& rejected = {},
                           const FeatureOverlayStyle& style = {});

// Colour of a track of the given lifetime (BGR).
cv::Scalar lifetimeColor(int track_count, int saturate_lifetime);

}  // namespace adugs::vio
