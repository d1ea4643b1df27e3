#pragma once
// Loading TorchScript files (libtorch) with errors that name the file, and checking the inputs
// and outputs a backend expects. Only the torch backends include this header.
#include <torch/script.h>

#include <string>
#include <unordered_map>
#include <vector>

namespace adugs::tracking {

// Loads `path` on the CPU in eval mode. `extra_files` (optional): names to read from the archive
// (e.g. ultralytics' "config.txt"); each is left empty when the file lacks it. Throws
// data::InputError naming the file when it is missing or not a TorchScript archive; `what` says
// what the file should be ("ultralytics YOLO TorchScript export", ...).
torch::jit::Module loadTorchScript(const std::string& path, const std::string& what,
                                   std::unordered_map<std::string, std::string>* extra_files = nullptr);

// Throws data::InputError naming the file unless `forward` takes exactly `input_names.size()`
// inputs besides self (the names are only for the message: "forward(image_embeddings, ...)").
void requireForwardInputs(const torch::jit::Module& module, const std::vector<std::string>& input_names,
                          const std::string& path, const std::string& what);

// Runs forward; a libtorch error (wrong input shapes inside the graph...) becomes a
// data::InputError naming the file and the input shapes.
c10::IValue runForward(torch::jit::Module& module, std::vector<c10::IValue> inputs, const std::string& path);

// "[1, 84, 8400]".
std::string shapeOf(const at::Tensor& tensor);

}  // namespace adugs::tracking
