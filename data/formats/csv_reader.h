#pragma once
// Streaming reader for the comma- (or space-) separated text files of EuRoC, TUM and MOT.
// It reads one row at a time, skips '#' comment lines, blank lines and a UTF-8 byte-order mark,
// accepts '\r\n' line ends, and converts fields with errors that name the file, line and column.
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace adugs::data {

// Strict, locale-independent number parsing shared by the CSV and YAML readers: the whole string
// must convert (an optional leading '+' is allowed). On failure *out_of_range tells overflow apart
// from bad syntax. parseDouble accepts "inf"/"nan": callers decide about finiteness.
bool parseInt64(const std::string& s, int64_t& out, bool* out_of_range = nullptr);
bool parseDouble(const std::string& s, double& out, bool* out_of_range = nullptr);

class CsvReader {
 public:
  enum class Separator { kComma, kWhitespace };

  // Throws InputError if the file cannot be opened.
  explicit CsvReader(const std::string& path, Separator sep = Separator::kComma);

  // Names used in error messages for columns 0..n-1 (optional; default "column N").
  void setColumnNames(std::vector<std::string> names) { names_ = std::move(names); }

  // Reads the next data row; false at end of file. A final line without '\n' is still read.
  bool next();

  // The current row.
  size_t size() const { return fields_.size(); }
  const std::string& field(size_t i) const;
  long lineNumber() const { return line_; }
  const std::string& path() const { return path_; }

  // Throws InputError unless the row has exactly n (or between lo and hi) fields.
  void requireColumns(size_t n) const { requireColumns(n, n); }
  void requireColumns(size_t lo, size_t hi) const;

  // Converters: the whole field must parse; doubles must be finite.
  int64_t int64At(size_t i) const;
  double doubleAt(size_t i) const;

  // Throws an InputError located at the current line.
  [[noreturn]] void fail(size_t column, const std::string& what) const;
  [[noreturn]] void failRow(const std::string& what) const;

 private:
  std::string columnName(size_t i) const;

  std::string path_;
  Separator sep_;
  std::ifstream in_;
  std::vector<std::string> names_;
  std::vector<std::string> fields_;
  long line_ = 0;
};

}  // namespace adugs::data
