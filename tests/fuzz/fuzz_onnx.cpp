// libFuzzer target: arbitrary bytes as an ONNX model for the hand-written protobuf reader that
// checks model signatures before OpenCV's importer runs (tracking/detect/onnx_signature).
// InputError is the expected outcome for bad input; any other exception, a crash, a hang or a
// sanitizer report is a bug.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "data/input_error.h"
#include "tracking/detect/onnx_signature.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const auto sig = adugs::tracking::parseOnnxSignature(bytes, "fuzz.onnx");
    for (const auto& t : sig.inputs) (void)adugs::tracking::describeShape(t);
  } catch (const adugs::data::InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "BUG: unexpected exception: %s\n", e.what());
    std::abort();
  }
  return 0;
}
