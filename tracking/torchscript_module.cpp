#include "tracking/torchscript_module.h"

#include <filesystem>

#include "data/input_error.h"

namespace adugs::tracking {

torch::jit::Module loadTorchScript(const std::string& path, const std::string& what,
                                   std::unordered_map<std::string, std::string>* extra_files) {
  if (!std::filesystem::is_regular_file(path)) throw data::InputError(path, 0, "model", what + " not found");
  torch::jit::ExtraFilesMap extra;
  if (extra_files)
    for (const auto& [name, content] : *extra_files) extra[name] = "";
  torch::jit::Module module;
  try {
    module = torch::jit::load(path, torch::kCPU, extra);
  } catch (const c10::Error& e) {
    throw data::InputError(path, 0, "model",
                           "libtorch cannot load it as a TorchScript archive (expected: " + what + "): " +
                               e.what_without_backtrace());
  } catch (const std::exception& e) {  // torch::jit::ErrorReport and friends
    throw data::InputError(path, 0, "model",
                           "libtorch cannot load it as a TorchScript archive (expected: " + what + "): " + e.what());
  }
  module.eval();
  if (extra_files)
    for (auto& [name, content] : *extra_files) content = extra[name];
  return module;
}

void requireForwardInputs(const torch::jit::Module& module, const std::vector<std::string>& input_names,
                          const std::string& path, const std::string& what) {
  std::string expected = "forward(";
  for (size_t i = 0; i < input_names.size(); ++i) expected += (i ? ", " : "") + input_names[i];
  expected += ")";
  const auto forward = module.find_method("forward");
  if (!forward) throw data::InputError(path, 0, "forward", "not a " + what + ": it has no forward method");
  const auto& arguments = forward->function().getSchema().arguments();
  std::string actual = "forward(";
  for (size_t i = 1; i < arguments.size(); ++i) actual += (i > 1 ? ", " : "") + arguments[i].name();
  actual += ")";
  if (arguments.size() != input_names.size() + 1)
    throw data::InputError(path, 0, "forward", "not a " + what + ": expected " + expected + ", the module has " + actual);
}

std::string shapeOf(const at::Tensor& tensor) {
  std::string s = "[";
  for (int64_t i = 0; i < tensor.dim(); ++i) s += (i ? ", " : "") + std::to_string(tensor.size(i));
  return s + "]";
}

c10::IValue runForward(torch::jit::Module& module, std::vector<c10::IValue> inputs, const std::string& path) {
  std::string shapes;
  for (const c10::IValue& v : inputs)
    if (v.isTensor()) shapes += (shapes.empty() ? "" : ", ") + shapeOf(v.toTensor());
  try {
    c10::InferenceMode no_autograd;
    return module.forward(std::move(inputs));
  } catch (const c10::Error& e) {
    throw data::InputError(path, 0, "forward",
                           "the model fails on inputs " + shapes + ": " + e.what_without_backtrace());
  } catch (const std::exception& e) {
    throw data::InputError(path, 0, "forward", std::string("the model fails: ") + e.what());
  }
}

}  // namespace adugs::tracking
