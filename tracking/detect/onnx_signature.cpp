#include "tracking/detect/onnx_signature.h"

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "data/input_error.h"

namespace adugs::tracking {
namespace {

// Field numbers from onnx.proto (ModelProto, GraphProto, NodeProto, ValueInfoProto, TypeProto,
// TensorShapeProto, TensorProto).
constexpr uint32_t kModelGraph = 7, kModelMetadataProps = 14;
constexpr uint32_t kEntryKey = 1, kEntryValue = 2;
constexpr uint32_t kGraphNode = 1, kGraphInitializer = 5, kGraphInput = 11, kGraphOutput = 12;
constexpr uint32_t kNodeOpType = 4;
constexpr uint32_t kTensorName = 8;
constexpr uint32_t kValueInfoName = 1, kValueInfoType = 2;
constexpr uint32_t kTypeTensor = 1, kTensorTypeShape = 2, kShapeDim = 1;
constexpr uint32_t kDimValue = 1;  // 2 is dim_param (a symbolic size): read as unknown

enum WireType : uint32_t { kVarint = 0, kFixed64 = 1, kBytes = 2, kFixed32 = 5 };

// One protobuf field of a message: number, wire type and its payload (varint or byte range).
struct Field {
  uint32_t number = 0;
  uint32_t wire = 0;
  uint64_t varint = 0;
  const char* data = nullptr;
  size_t size = 0;
  std::string text() const { return std::string(data, size); }
};

// Walks the fields of one serialized message; throws std::runtime_error on malformed bytes.
class MessageReader {
 public:
  MessageReader(const char* begin, size_t size) : p_(begin), end_(begin + size) {}
  explicit MessageReader(const Field& f) : MessageReader(f.data, f.size) {}

  bool next(Field* f) {
    if (p_ == end_) return false;
    const uint64_t key = readVarint();
    f->number = static_cast<uint32_t>(key >> 3);
    f->wire = static_cast<uint32_t>(key & 7);
    if (f->number == 0) throw std::runtime_error("field number 0");
    switch (f->wire) {
      case kVarint:
        f->varint = readVarint();
        break;
      case kFixed64:
        skip(8);
        break;
      case kFixed32:
        skip(4);
        break;
      case kBytes: {
        const uint64_t n = readVarint();
        if (n > static_cast<uint64_t>(end_ - p_)) throw std::runtime_error("length past the end");
        f->data = p_;
        f->size = static_cast<size_t>(n);
        p_ += n;
        break;
      }
      default:
        throw std::runtime_error("unsupported wire type " + std::to_string(f->wire));
    }
    return true;
  }

 private:
  uint64_t readVarint() {
    uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (p_ == end_) throw std::runtime_error("truncated varint");
      const auto byte = static_cast<unsigned char>(*p_++);
      value |= static_cast<uint64_t>(byte & 0x7f) << shift;
      if (!(byte & 0x80)) return value;
    }
    throw std::runtime_error("varint too long");
  }
  void skip(size_t n) {
    if (n > static_cast<size_t>(end_ - p_)) throw std::runtime_error("truncated fixed field");
    p_ += n;
  }
  const char* p_;
  const char* end_;
};

int64_t parseDim(const Field& dim_field) {
  MessageReader r(dim_field);
  Field f;
  int64_t value = -1;
  while (r.next(&f))
    if (f.number == kDimValue && f.wire == kVarint) value = static_cast<int64_t>(f.varint);
  return value;  // dim_param (symbolic) or nothing: unknown
}

OnnxTensorInfo parseValueInfo(const Field& value_info) {
  OnnxTensorInfo info;
  MessageReader r(value_info);
  Field f;
  while (r.next(&f)) {
    if (f.number == kValueInfoName && f.wire == kBytes) info.name = f.text();
    if (f.number != kValueInfoType || f.wire != kBytes) continue;
    MessageReader type(f);
    Field t;
    while (type.next(&t)) {
      if (t.number != kTypeTensor || t.wire != kBytes) continue;
      MessageReader tensor(t);
      Field s;
      while (tensor.next(&s)) {
        if (s.number != kTensorTypeShape || s.wire != kBytes) continue;
        info.has_shape = true;
        MessageReader shape(s);
        Field d;
        while (shape.next(&d))
          if (d.number == kShapeDim && d.wire == kBytes) info.dims.push_back(parseDim(d));
      }
    }
  }
  return info;
}

std::string stringField(const Field& message, uint32_t number) {
  MessageReader r(message);
  Field f;
  while (r.next(&f))
    if (f.number == number && f.wire == kBytes) return f.text();
  return {};
}

OnnxSignature parseGraph(const Field& graph) {
  OnnxSignature sig;
  std::vector<OnnxTensorInfo> declared_inputs;
  std::set<std::string> initializers;
  MessageReader r(graph);
  Field f;
  while (r.next(&f)) {
    if (f.wire != kBytes) continue;
    if (f.number == kGraphNode) sig.op_types.push_back(stringField(f, kNodeOpType));
    if (f.number == kGraphInitializer) initializers.insert(stringField(f, kTensorName));
    if (f.number == kGraphInput) declared_inputs.push_back(parseValueInfo(f));
    if (f.number == kGraphOutput) sig.outputs.push_back(parseValueInfo(f));
  }
  // Older exports also list the weights as graph inputs; only the others are fed by the caller.
  for (OnnxTensorInfo& in : declared_inputs)
    if (!initializers.count(in.name)) sig.inputs.push_back(std::move(in));
  return sig;
}

}  // namespace

OnnxSignature parseOnnxSignature(const std::string& content, const std::string& name) {
  try {
    MessageReader model(content.data(), content.size());
    Field f;
    std::map<std::string, std::string> metadata;
    bool found = false;
    OnnxSignature sig;
    while (model.next(&f)) {
      if (f.wire != kBytes) continue;
      if (f.number == kModelMetadataProps)
        metadata[stringField(f, kEntryKey)] = stringField(f, kEntryValue);
      if (f.number != kModelGraph) continue;
      sig = parseGraph(f);
      found = true;
    }
    if (!found) throw std::runtime_error("no graph found");
    if (sig.inputs.empty() || sig.outputs.empty() || sig.op_types.empty())
      throw std::runtime_error("the graph has no inputs, outputs or nodes");
    sig.metadata = std::move(metadata);
    return sig;
  } catch (const std::runtime_error& e) {
    throw data::InputError(name, 0, "", std::string("not a valid ONNX model (") + e.what() + ")");
  }
}

OnnxSignature readOnnxSignature(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw data::InputError(path, 0, "", "cannot open the ONNX model file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parseOnnxSignature(bytes.str(), path);
}

std::string describeShape(const OnnxTensorInfo& tensor) {
  if (!tensor.has_shape) return "[unknown]";
  std::string s = "[";
  for (size_t i = 0; i < tensor.dims.size(); ++i) {
    if (i) s += ", ";
    s += tensor.dims[i] < 0 ? "?" : std::to_string(tensor.dims[i]);
  }
  return s + "]";
}

}  // namespace adugs::tracking
