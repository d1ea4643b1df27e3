#include "data/formats/number_text.h"

#include <charconv>

namespace adugs::data {

std::string shortestText(double value) {
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof(buf), value);
  return std::string(buf, res.ptr);
}

std::string listText(const std::vector<double>& values) {
  std::string s = "[";
  for (size_t i = 0; i < values.size(); ++i) s += (i ? ", " : "") + shortestText(values[i]);
  return s + "]";
}

}  // namespace adugs::data
