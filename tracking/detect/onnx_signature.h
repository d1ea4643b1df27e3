#pragma once
// The declared interface of an ONNX model: graph input names and shapes (initializers excluded),
// output names and shapes, the node op types and the metadata entries. Read straight from the
// protobuf wire format so a model can be told apart (YOLOX or ultralytics layout) and rejected
// with a message naming what is wrong before OpenCV's importer runs, without a protobuf dependency.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace adugs::tracking {

struct OnnxTensorInfo {
  std::string name;
  bool has_shape = false;
  std::vector<int64_t> dims;  // -1 for a symbolic or unknown dimension
};

struct OnnxSignature {
  std::vector<OnnxTensorInfo> inputs;
  std::vector<OnnxTensorInfo> outputs;
  std::vector<std::string> op_types;  // one per node, in graph order
  // The model's metadata_props (ultralytics stores "names", "imgsz", "task", "stride" there).
  std::map<std::string, std::string> metadata;
};

// Throws data::InputError naming the file when it is missing, unreadable or not an ONNX model.
OnnxSignature readOnnxSignature(const std::string& path);
// The same from the file's bytes; `name` goes into error messages.
OnnxSignature parseOnnxSignature(const std::string& content, const std::string& name);

// "[1, 256, 64, 64]", "?" for symbolic dimensions, "[unknown]" without a declared shape.
std::string describeShape(const OnnxTensorInfo& tensor);

}  // namespace adugs::tracking
