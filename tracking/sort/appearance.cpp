#include "tracking/sort/appearance.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace adugs::tracking {

cv::Mat boxHistogram(const cv::Mat& image, const Box& box) {
  const Box core{box.cx, box.cy, 0.6 * box.w, 0.8 * box.h};
  const cv::Rect r = cv::Rect(static_cast<int>(std::floor(core.left())), static_cast<int>(std::floor(core.top())),
                              static_cast<int>(std::ceil(core.w)), static_cast<int>(std::ceil(core.h))) &
                     cv::Rect(0, 0, image.cols, image.rows);
  if (r.area() < 4) return {};
  cv::Mat hist;
  if (image.channels() == 3) {
    cv::Mat hsv;
    cv::cvtColor(image(r), hsv, cv::COLOR_BGR2HSV);
    const int channels[] = {0, 1}, bins[] = {8, 4};
    const float hue[] = {0, 180}, sat[] = {0, 256};
    const float* ranges[] = {hue, sat};
    cv::calcHist(&hsv, 1, channels, cv::Mat(), hist, 2, bins, ranges);
    hist = hist.reshape(1, 32);
  } else {
    const cv::Mat grey = image(r);
    const int channels[] = {0}, bins[] = {16};
    const float range[] = {0, 256};
    const float* ranges[] = {range};
    cv::calcHist(&grey, 1, channels, cv::Mat(), hist, 1, bins, ranges);
  }
  hist /= std::max(1.0, cv::sum(hist)[0]);
  return hist;
}

double histogramSimilarity(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty() || a.total() != b.total()) return 0.0;
  double bc = 0;
  for (int i = 0; i < static_cast<int>(a.total()); ++i) bc += std::sqrt(a.at<float>(i) * b.at<float>(i));
  return bc;
}

}  // namespace adugs::tracking
