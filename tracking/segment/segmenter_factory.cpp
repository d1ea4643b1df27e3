#include "tracking/segment/segmenter_factory.h"

#include <stdexcept>

#include "tracking/segment/grabcut_segmenter.h"
#include "tracking/torch_plugin_loader.h"

namespace adugs::tracking {

std::unique_ptr<BoxSegmenter> makeBoxSegmenter(const std::string& kind, const std::string& encoder,
                                               const std::string& decoder, const GrabCutOptions& grabcut) {
  if (kind.empty() || kind == "grabcut") return std::make_unique<GrabCutSegmenter>(grabcut);
  if (kind == "box") return std::make_unique<FilledBoxSegmenter>();
  if (kind == "mobilesam") {
    if (encoder.empty() || decoder.empty())
      throw std::invalid_argument(
          "segmenter 'mobilesam' needs both TorchScript files: --sam-encoder mobilesam_encoder.pt "
          "--sam-decoder mobilesam_decoder.pt (written by scripts/export_mobilesam.py)");
    return makeMobileSamSegmenter(encoder, decoder);  // libtorch, loaded now
  }
  throw std::invalid_argument("unknown segmenter '" + kind +
                              "' (expected grabcut, box or mobilesam)");
}

}  // namespace adugs::tracking
