#pragma once
// Builds the box segmenter the user asked for: "grabcut" (weight-free default), "box" (filled
// boxes) or "mobilesam" (the encoder and decoder TorchScript files of scripts/export_mobilesam.py;
// see mobilesam_segmenter.h; needs a build with libtorch).
#include <memory>
#include <string>

#include "tracking/segment/box_segmenter.h"

namespace adugs::tracking {

// Throws std::invalid_argument for an unknown kind, "mobilesam" without both paths or in a build
// without libtorch, and data::InputError (naming the file) for models that cannot be used.
std::unique_ptr<BoxSegmenter> makeBoxSegmenter(const std::string& kind = "grabcut",
                                               const std::string& encoder = "",
                                               const std::string& decoder = "");

}  // namespace adugs::tracking
