#include "tracking/segment/segmenter_factory.h"

#include <stdexcept>

#include "tracking/segment/grabcut_segmenter.h"
#ifdef ADUGS_HAVE_TORCH
#include "tracking/segment/mobilesam_segmenter.h"
#endif

namespace adugs::tracking {

std::unique_ptr<BoxSegmenter> makeBoxSegmenter(const std::string& kind, const std::string& encoder,
                                               const std::string& decoder) {
  if (kind.empty() || kind == "grabcut") return std::make_unique<GrabCutSegmenter>();
  if (kind == "box") return std::make_unique<FilledBoxSegmenter>();
  if (kind == "mobilesam") {
    if (encoder.empty() || decoder.empty())
      throw std::invalid_argument(
          "segmenter 'mobilesam' needs both TorchScript files: --sam-encoder mobilesam_encoder.pt "
          "--sam-decoder mobilesam_decoder.pt (written by scripts/export_mobilesam.py)");
#ifdef ADUGS_HAVE_TORCH
    return std::make_unique<MobileSamSegmenter>(encoder, decoder);
#else
    throw std::invalid_argument(
        "segmenter 'mobilesam' needs libtorch, and this adugs was built without it: install Debian's "
        "libtorch-dev (scripts/setup.sh does) and rebuild");
#endif
  }
  throw std::invalid_argument("unknown segmenter '" + kind +
                              "' (expected grabcut, box or mobilesam)");
}

}  // namespace adugs::tracking
