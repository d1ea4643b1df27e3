#pragma once
// Builds the box segmenter the user asked for: "grabcut" (weight-free default), "box" (filled
// boxes) or "mobilesam" (the encoder and decoder TorchScript files of scripts/export_mobilesam.py;
// see mobilesam_segmenter.h; needs a build with libtorch, whose module is loaded then).
#include <memory>
#include <string>

#include "tracking/segment/box_segmenter.h"
#include "tracking/segment/grabcut_segmenter.h"

namespace adugs::tracking {

// Throws std::invalid_argument for an unknown kind or "mobilesam" without both paths, and
// data::InputError (naming the file) for models that cannot be used or a build without libtorch.
// grabcut: the GrabCut segmenter's options (the run config's dynamic: grabcut: map).
std::unique_ptr<BoxSegmenter> makeBoxSegmenter(const std::string& kind = "grabcut",
                                               const std::string& encoder = "",
                                               const std::string& decoder = "",
                                               const GrabCutOptions& grabcut = {});

}  // namespace adugs::tracking
