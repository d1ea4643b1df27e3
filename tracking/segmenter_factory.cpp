#include "tracking/segmenter_factory.h"

#include <stdexcept>

#include "tracking/grabcut_segmenter.h"
#include "tracking/mobilesam_segmenter.h"

namespace adugs::tracking {

std::unique_ptr<BoxSegmenter> makeBoxSegmenter(const std::string& kind, const std::string& encoder,
                                               const std::string& decoder) {
  if (kind.empty() || kind == "grabcut") return std::make_unique<GrabCutSegmenter>();
  if (kind == "box") return std::make_unique<FilledBoxSegmenter>();
  if (kind == "mobilesam") {
    if (encoder.empty() || decoder.empty())
      throw std::invalid_argument(
          "segmenter 'mobilesam' needs both the encoder and the decoder ONNX file");
    return std::make_unique<MobileSamSegmenter>(encoder, decoder);
  }
  throw std::invalid_argument("unknown segmenter '" + kind +
                              "' (expected grabcut, box or mobilesam)");
}

}  // namespace adugs::tracking
