// libFuzzer target: arbitrary bytes as an ONNX model for the hand-written protobuf reader that
// checks model signatures before OpenCV's importer runs (tracking/detect/onnx_signature).
// InputError is the expected outcome for bad input; any other exception, a crash, a hang or a
// sanitizer report is a bug. Oracle: a signature that parses is written back as a minimal ONNX
// model (the fields the reader looks at, protobuf wire format) and must parse to the same
// signature.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "data/input_error.h"
#include "tracking/detect/onnx_signature.h"

namespace {
using adugs::tracking::OnnxSignature;
using adugs::tracking::OnnxTensorInfo;

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "BUG: %s\n", what.c_str());
  std::abort();
}

void varint(std::string& out, uint64_t v) {
  while (v >= 0x80) {
    out += static_cast<char>((v & 0x7f) | 0x80);
    v >>= 7;
  }
  out += static_cast<char>(v);
}

// A length-delimited field (wire type 2).
void bytesField(std::string& out, uint32_t number, const std::string& payload) {
  varint(out, (static_cast<uint64_t>(number) << 3) | 2);
  varint(out, payload.size());
  out += payload;
}

// ONNX's field numbers: ModelProto.graph 7, .metadata_props 14 (key 1, value 2); GraphProto.node 1,
// .input 11, .output 12; NodeProto.op_type 4; ValueInfoProto.name 1, .type 2; TypeProto.tensor_type
// 1; Tensor.shape 2; TensorShapeProto.dim 1; Dimension.dim_value 1 (varint).
std::string valueInfo(const OnnxTensorInfo& t) {
  std::string v;
  bytesField(v, 1, t.name);
  if (t.has_shape) {
    std::string shape;
    for (int64_t d : t.dims) {
      std::string dim;
      varint(dim, (1u << 3) | 0);
      varint(dim, static_cast<uint64_t>(d));
      bytesField(shape, 1, dim);
    }
    std::string tensor, type;
    bytesField(tensor, 2, shape);
    bytesField(type, 1, tensor);
    bytesField(v, 2, type);
  }
  return v;
}

std::string serialise(const OnnxSignature& sig) {
  std::string graph;
  for (const std::string& op : sig.op_types) {
    std::string node;
    bytesField(node, 4, op);
    bytesField(graph, 1, node);
  }
  for (const auto& in : sig.inputs) bytesField(graph, 11, valueInfo(in));
  for (const auto& out : sig.outputs) bytesField(graph, 12, valueInfo(out));
  std::string model;
  bytesField(model, 7, graph);
  for (const auto& [key, value] : sig.metadata) {
    std::string entry;
    bytesField(entry, 1, key);
    bytesField(entry, 2, value);
    bytesField(model, 14, entry);
  }
  return model;
}

bool same(const std::vector<OnnxTensorInfo>& a, const std::vector<OnnxTensorInfo>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].name != b[i].name || a[i].has_shape != b[i].has_shape || a[i].dims != b[i].dims) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const OnnxSignature sig = adugs::tracking::parseOnnxSignature(bytes, "fuzz.onnx");
    for (const auto& t : sig.inputs) (void)adugs::tracking::describeShape(t);
    OnnxSignature back;
    try {
      back = adugs::tracking::parseOnnxSignature(serialise(sig), "written.onnx");
    } catch (const adugs::data::InputError& e) {
      bug(std::string("a parsed signature written back does not parse: ") + e.what());
    }
    if (!same(sig.inputs, back.inputs) || !same(sig.outputs, back.outputs) || sig.op_types != back.op_types ||
        sig.metadata != back.metadata)
      bug("a parsed signature written back parses differently");
  } catch (const adugs::data::InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "BUG: unexpected exception: %s\n", e.what());
    std::abort();
  }
  return 0;
}
