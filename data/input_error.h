#pragma once
// The one exception type for bad user input (files, CSV rows, YAML keys, CLI values).
// Its message always names where the problem is: "FILE:LINE: field 'NAME': what went wrong".
#include <stdexcept>
#include <string>

namespace adugs::data {

class InputError : public std::runtime_error {
 public:
  // line <= 0 means "no line" (e.g. a missing file); field may be empty.
  InputError(const std::string& file, long line, const std::string& field, const std::string& what);

  const std::string& file() const { return file_; }
  long line() const { return line_; }
  const std::string& field() const { return field_; }

 private:
  std::string file_;
  long line_;
  std::string field_;
};

}  // namespace adugs::data
