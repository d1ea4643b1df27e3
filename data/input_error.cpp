#include "data/input_error.h"

namespace adugs::data {
namespace {
std::string formatMessage(const std::string& file, long line, const std::string& field,
                          const std::string& what) {
  std::string msg = file;
  if (line > 0) msg += ":" + std::to_string(line);
  msg += ": ";
  if (!field.empty()) msg += "field '" + field + "': ";
  return msg + what;
}
}  // namespace

InputError::InputError(const std::string& file, long line, const std::string& field,
                       const std::string& what)
    : std::runtime_error(formatMessage(file, line, field, what)),
      file_(file),
      line_(line),
      field_(field) {}

}  // namespace adugs::data
