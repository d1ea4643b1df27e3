#pragma once
// A cheap appearance cue for SORT's association (no network weights): the normalised histogram of
// a box's pixels - hue x saturation (8 x 4 bins) for colour images, 16 grey levels for grey ones -
// compared by the Bhattacharyya coefficient. It separates people in different clothes when their
// boxes cross, where IoU alone swaps identities.
#include <vector>

#include <opencv2/core.hpp>

#include "tracking/box.h"

namespace adugs::tracking {

// CV_32F column histogram summing to 1 (empty Mat for a box outside the image). image: CV_8UC1 or
// CV_8UC3 BGR. Only the central 60 % of the box's width and 80 % of its height are used (less
// background around a person).
cv::Mat boxHistogram(const cv::Mat& image, const Box& box);

// Bhattacharyya coefficient of two normalised histograms: 1 = identical, 0 = disjoint.
double histogramSimilarity(const cv::Mat& a, const cv::Mat& b);

}  // namespace adugs::tracking
