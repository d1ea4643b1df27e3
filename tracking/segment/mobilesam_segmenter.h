#pragma once
// Box-prompted segmentation with MobileSAM (or a SAM-family model of the same interface) exported
// to TorchScript by scripts/export_mobilesam.py and run with libtorch:
//   mobilesam_encoder.pt  forward(image [1, 3, 1024, 1024]) -> image embeddings [1, 256, 64, 64]
//       (the image already SAM-preprocessed: tracking/segment/sam_transforms.h), once per frame;
//   mobilesam_decoder.pt  forward(image_embeddings [1, 256, 64, 64], point_coords [1, N, 2],
//       point_labels [1, N]) -> (low_res_masks [1, 1, 256, 256] logits, iou_predictions [1, 1]),
//       once per box; a box is prompted as SAM does: its corners in the resized 1024 frame with
//       labels 2 (top-left) and 3 (bottom-right).
// Pixels with mask logit > 0 inside the box are the object. Like GrabCut, a box whose mask
// covers (almost) nothing is filled instead: for the VIO, masking too much is the safe error.
// Built when libtorch (Debian libtorch-dev) is present.
#include <memory>
#include <string>

#include "tracking/segment/box_segmenter.h"

namespace adugs::tracking {

struct MobileSamOptions {
  double min_foreground_fraction = 0.15;  // of the clipped box area; less -> fill the box
};

class MobileSamSegmenter : public BoxSegmenter {
 public:
  // Throws data::InputError naming the file when a model is missing, not TorchScript, takes other
  // inputs than the interface above, or (decoder: checked with one dry run) returns other shapes.
  MobileSamSegmenter(const std::string& encoder_path, const std::string& decoder_path,
                     const MobileSamOptions& options = {});
  ~MobileSamSegmenter() override;
  cv::Mat segment(const cv::Mat& image, const std::vector<Box>& boxes) override;
  const char* name() const override { return "mobilesam"; }
  bool slow() const override { return true; }
  int refreshEvery() const override { return 10; }
  // How many boxes fell back to the filled box in the last call.
  int lastFallbacks() const { return fallbacks_; }

 private:
  struct Models;
  std::unique_ptr<Models> models_;
  std::string encoder_path_;
  std::string decoder_path_;
  MobileSamOptions options_;
  int fallbacks_ = 0;
};

}  // namespace adugs::tracking
