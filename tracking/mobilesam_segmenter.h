#pragma once
// Box-prompted segmentation with MobileSAM (or any Segment Anything model) exported to ONNX:
// the image encoder (one input 1x3x1024x1024 - SAM's export names it "x", others "images" - and
// one output "image_embeddings" 1x256x64x64) runs once per frame; the prompt decoder exported by
// segment-anything's scripts/export_onnx_model.py (inputs image_embeddings, point_coords,
// point_labels, mask_input, has_mask_input, orig_im_size; outputs masks, iou_predictions,
// low_res_masks) runs once per box. Both run with OpenCV dnn. A box is prompted as SAM's ONNX
// example does: its corners in the resized 1024 frame with labels 2 (top-left) and 3
// (bottom-right), no padding point (the example adds one only when there is no box).
// Pixels with mask logit > 0 inside the box are the object. Like GrabCut, a box whose mask
// covers (almost) nothing is filled instead: for the VIO, masking too much is the safe error.
#include <opencv2/dnn.hpp>
#include <string>

#include "tracking/box_segmenter.h"

namespace adugs::tracking {

struct MobileSamOptions {
  double min_foreground_fraction = 0.15;  // of the clipped box area; less -> fill the box
};

class MobileSamSegmenter : public BoxSegmenter {
 public:
  // Throws data::InputError naming the file when a model is missing or not ONNX, when its
  // inputs/outputs are not SAM's (names and shapes), or when OpenCV's importer rejects a node
  // (the message names the node's op type).
  MobileSamSegmenter(const std::string& encoder_path, const std::string& decoder_path,
                     const MobileSamOptions& options = {});
  cv::Mat segment(const cv::Mat& image, const std::vector<Box>& boxes) override;
  const char* name() const override { return "mobilesam"; }
  // How many boxes fell back to the filled box in the last call.
  int lastFallbacks() const { return fallbacks_; }

 private:
  cv::Mat encode(const cv::Mat& image);
  // Mask logits of the whole image (CV_32F) for one box prompt.
  cv::Mat decode(const cv::Mat& embeddings, const Box& box, cv::Size image_size);

  std::string encoder_path_;
  std::string decoder_path_;
  std::string encoder_input_;  // the encoder's (single) input name
  MobileSamOptions options_;
  cv::dnn::Net encoder_;
  cv::dnn::Net decoder_;
  int fallbacks_ = 0;
};

}  // namespace adugs::tracking
