#pragma once
// The fixed image/prompt/mask transforms around Segment Anything's (and MobileSAM's) ONNX graphs,
// as segment-anything's ResizeLongestSide, SamPredictor and SamOnnxModel.mask_postprocessing
// define them: the image is resized so its longest side is 1024 px, normalised with SAM's pixel
// mean/std (RGB) and zero-padded bottom/right to 1024 x 1024; prompts are given in that resized
// frame; low-resolution mask logits (256 x 256 over the padded 1024 frame) are upscaled to
// 1024, cropped to the resized image and resized to the original image size.
#include <opencv2/core.hpp>

#include "tracking/box.h"

namespace adugs::tracking {

constexpr int kSamImageSize = 1024;      // encoder input side
constexpr int kSamEmbeddingSize = 64;    // image_embeddings spatial side
constexpr int kSamEmbeddingDim = 256;    // image_embeddings channels
constexpr int kSamLowResMaskSize = 256;  // mask_input / low_res_masks side

// Size of the image after resizing its longest side to 1024 (rounded as SAM: floor(x + 0.5)).
cv::Size samResizedSize(cv::Size image_size);

// The 1 x 3 x 1024 x 1024 float encoder input from an 8-bit grey or BGR image.
cv::Mat samEncoderInput(const cv::Mat& image);

// Box corners (x0, y0, x1, y1) mapped into the resized frame: x * (resized_w / w), y likewise.
cv::Vec4f samBoxPrompt(const Box& box, cv::Size image_size);

// Mask logits of the original image size (CV_32F) from a 256 x 256 low-resolution logit map.
cv::Mat samUpscaleLowResMask(const cv::Mat& low_res_logits, cv::Size image_size);

}  // namespace adugs::tracking
