#pragma once
// The libtorch backends (ultralytics TorchScript detector, MobileSAM) live in a module,
// libadugs_torch.so, that adugs opens only when a TorchScript model is given: once loaded,
// libtorch alone takes about 160 MB of memory and 0.3 s, which every other command (a plain
// `adugs run`, `adugs --help`) no longer pays. This header is the contract between the binary
// (tracking/torch_plugin_loader) and the module (tracking/torch_plugin.cpp): two C entry points
// that hand over C++ objects (one compiler and standard library for both) and throw what the
// backends throw (data::InputError naming the file).
#include <string>

namespace adugs::tracking {

// Declared only: a base file of tracking/ (included by detect/ and segment/) names no sub-folder.
class Detector;
class BoxSegmenter;

inline constexpr const char* kTorchModuleFile = "libadugs_torch.so";
inline constexpr const char* kMakeTorchDetectorSymbol = "adugs_torch_make_detector";
inline constexpr const char* kMakeMobileSamSymbol = "adugs_torch_make_mobilesam";

// The caller owns the returned object.
using MakeTorchDetector = Detector* (*)(const std::string& model_path);
using MakeMobileSam = BoxSegmenter* (*)(const std::string& encoder_path, const std::string& decoder_path);

}  // namespace adugs::tracking
