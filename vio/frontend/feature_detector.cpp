#include "vio/frontend/feature_detector.h"

#include <opencv2/features2d.hpp>

namespace adugs::vio {

void detectOrbCorners(const cv::Mat& image, const cv::Mat& detection_mask,
                      const FeatureTrackerOptions& options, std::vector<cv::KeyPoint>* corners) {
  corners->clear();
  cv::FAST(image, *corners, options.fast_threshold, true, cv::FastFeatureDetector::TYPE_9_16);
  // Same filter order as ORB: mask, image border, then the strongest.
  if (!detection_mask.empty()) cv::KeyPointsFilter::runByPixelsMask(*corners, detection_mask);
  cv::KeyPointsFilter::runByImageBorder(*corners, image.size(), options.detection_border_px);
  cv::KeyPointsFilter::retainBest(*corners, options.max_candidates);
}

}  // namespace adugs::vio
