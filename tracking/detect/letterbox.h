#pragma once
// Letterbox resizing into a detector's fixed input: the image is scaled by one factor (aspect
// kept) and padded with grey 114. The two YOLO families place and round it differently, and a
// detector must undo exactly what was done, so both rules live here:
//   kTopLeft (YOLOX's preproc): r = min(H/h, W/w), resized to (int(w r), int(h r)) (truncated),
//     placed at the top-left corner.
//   kCentred (ultralytics' LetterBox for predict): resized to (round(w r), round(h r)), padding
//     split around it: left = round(dw - 0.1), top = round(dh - 0.1), dw = (W - w') / 2.
// A box in input pixels maps back to the image as x = (x_in - left) / r.
#include <opencv2/core.hpp>

#include "tracking/box.h"

namespace adugs::tracking {

enum class LetterboxPlacement { kTopLeft, kCentred };

struct Letterbox {
  cv::Mat image;          // the network input, CV_8UC3 BGR, of the requested size
  double scale = 1.0;     // r
  cv::Point2d offset;     // (left, top) padding in input pixels
  // A box in network-input pixels back in original image pixels.
  Box toImage(const Box& input_box) const;
};

// image: CV_8UC1 or CV_8UC3 BGR.
Letterbox letterbox(const cv::Mat& image, cv::Size input_size, LetterboxPlacement placement);

}  // namespace adugs::tracking
