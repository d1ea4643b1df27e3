#include "data/formats/csv_reader.h"

#include <charconv>
#include <cmath>
#include <filesystem>

#include "data/input_error.h"

namespace adugs::data {
namespace {

std::string trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// from_chars rejects a leading '+'; allow exactly one (but not "+-1").
bool stripPlus(const std::string& s, const char*& b, const char* e) {
  b = s.data();
  if (b != e && *b == '+') {
    ++b;
    if (b == e || *b == '-' || *b == '+') return false;
  }
  return b != e;
}

template <typename T>
bool parseNumber(const std::string& s, T& out, bool* out_of_range) {
  if (out_of_range) *out_of_range = false;
  const char* e = s.data() + s.size();
  const char* b = nullptr;
  if (!stripPlus(s, b, e)) return false;
  T v{};
  auto [p, ec] = std::from_chars(b, e, v);
  if (ec == std::errc::result_out_of_range && p == e) {
    if (out_of_range) *out_of_range = true;
    return false;
  }
  if (ec != std::errc() || p != e) return false;
  out = v;
  return true;
}

}  // namespace

bool parseInt64(const std::string& s, int64_t& out, bool* out_of_range) {
  return parseNumber(s, out, out_of_range);
}

bool parseDouble(const std::string& s, double& out, bool* out_of_range) {
  return parseNumber(s, out, out_of_range);
}

CsvReader::CsvReader(const std::string& path, Separator sep) : path_(path), sep_(sep), in_(path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, 0, "", "is a folder, not a file");
  if (!in_) throw InputError(path, 0, "", "cannot open file");
}

bool CsvReader::next() {
  std::string line;
  while (std::getline(in_, line)) {
    ++line_;
    if (line_ == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    fields_.clear();
    if (sep_ == Separator::kComma) {
      size_t start = 0;
      while (true) {
        size_t comma = t.find(',', start);
        fields_.push_back(trim(t.substr(start, comma - start)));
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    } else {
      size_t pos = 0;
      while (pos < t.size()) {
        size_t b = t.find_first_not_of(" \t", pos);
        if (b == std::string::npos) break;
        size_t e = t.find_first_of(" \t", b);
        fields_.push_back(t.substr(b, e == std::string::npos ? std::string::npos : e - b));
        pos = e == std::string::npos ? t.size() : e;
      }
    }
    return true;
  }
  if (in_.bad()) throw InputError(path_, line_, "", "read error");
  return false;
}

const std::string& CsvReader::field(size_t i) const {
  if (i >= fields_.size()) fail(i, "missing (row has " + std::to_string(fields_.size()) + " fields)");
  return fields_[i];
}

void CsvReader::requireColumns(size_t lo, size_t hi) const {
  if (fields_.size() < lo || fields_.size() > hi) {
    std::string want = lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi);
    failRow("expected " + want + " fields, found " + std::to_string(fields_.size()) +
            " (truncated or malformed line?)");
  }
}

int64_t CsvReader::int64At(size_t i) const {
  const std::string& s = field(i);
  if (s.empty()) fail(i, "empty value");
  int64_t v = 0;
  bool overflow = false;
  if (!parseInt64(s, v, &overflow))
    fail(i, (overflow ? "integer out of range: '" : "not an integer: '") + s + "'");
  return v;
}

double CsvReader::doubleAt(size_t i) const {
  const std::string& s = field(i);
  if (s.empty()) fail(i, "empty value");
  double v = 0;
  bool overflow = false;
  if (!parseDouble(s, v, &overflow) && !overflow) fail(i, "not a number: '" + s + "'");
  if (overflow) fail(i, "number out of range: '" + s + "'");
  if (!std::isfinite(v)) fail(i, "value is not finite: '" + s + "'");
  return v;
}

std::string CsvReader::columnName(size_t i) const {
  if (i < names_.size()) return names_[i];
  return "column " + std::to_string(i + 1);
}

void CsvReader::fail(size_t column, const std::string& what) const {
  throw InputError(path_, line_, columnName(column), what);
}

void CsvReader::failRow(const std::string& what) const { throw InputError(path_, line_, "", what); }

}  // namespace adugs::data
