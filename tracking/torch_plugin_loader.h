#pragma once
// Opens libadugs_torch.so (tracking/torch_plugin.h) the first time a TorchScript model is used,
// and keeps it open for the life of the process. Where it looks, first match:
//   $ADUGS_TORCH_MODULE (a path; when set, the only place looked at),
//   next to the running executable (the build puts it beside app/adugs),
//   where this build wrote it (for the test executables).
#include <memory>
#include <string>

namespace adugs::tracking {

// Declared only: a base file of tracking/ (included by detect/ and segment/) names no sub-folder.
class Detector;
class BoxSegmenter;

// data::InputError naming the model file (field `what`) when the module cannot be found or
// opened (with the loader's reason and how to get it); the backend's own errors otherwise.
std::unique_ptr<Detector> makeTorchScriptDetector(const std::string& model_path);
std::unique_ptr<BoxSegmenter> makeMobileSamSegmenter(const std::string& encoder_path,
                                                     const std::string& decoder_path);

// Where the module would be loaded from ("" when nowhere), without loading it.
std::string torchModulePath();

}  // namespace adugs::tracking
