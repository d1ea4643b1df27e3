// The entry points of libadugs_torch.so (tracking/torch_plugin.h): built only into that module.
#include "tracking/torch_plugin.h"

#include "tracking/detect/torchscript_detector.h"
#include "tracking/segment/mobilesam_segmenter.h"

extern "C" {

// Checked against the loader's function pointer types at compile time below.
adugs::tracking::Detector* adugs_torch_make_detector(const std::string& model_path) {
  return new adugs::tracking::TorchScriptDetector(model_path);
}

adugs::tracking::BoxSegmenter* adugs_torch_make_mobilesam(const std::string& encoder_path,
                                                         const std::string& decoder_path) {
  return new adugs::tracking::MobileSamSegmenter(encoder_path, decoder_path);
}

}  // extern "C"

static_assert(std::is_same_v<decltype(&adugs_torch_make_detector), adugs::tracking::MakeTorchDetector>);
static_assert(std::is_same_v<decltype(&adugs_torch_make_mobilesam), adugs::tracking::MakeMobileSam>);
