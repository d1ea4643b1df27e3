#pragma once
// Strict loading of options structs from YAML (the OpenVINS VioManagerOptions pattern): the struct
// holds the defaults, the YAML file overrides some of them, and a key nobody asked for is an error.
//
//   TrackerOptions o;                                        // defaults in code
//   YamlOptionsReader r = YamlOptionsReader::fromFile(path);
//   r.optional("max_features", o.max_features, 1, 5000);    // kept when absent, range-checked
//   r.optional("use_klt", o.use_klt);
//   YamlOptionsReader m = r.child("masker");                 // nested map -> nested struct
//   m.optional("erode_px", o.masker.erode_px);
//   m.finish();
//   r.finish();                                              // throws for an unknown key
//
// Every problem is an InputError naming the file, the line of the key (from YAML::Mark) and the
// key path ("masker.erode_px"). Numbers are parsed strictly: the whole scalar must convert, doubles
// must be finite, integers must not be written as "3.0" or overflow. Booleans are true/false.
// Duplicate keys and non-scalar keys are errors.
#include <cstdint>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace adugs::data {
namespace detail {
template <typename T>
struct NonDeducedT {
  using type = T;
};
template <typename T>
std::string numberText(const T& v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
}  // namespace detail
// Keeps range bounds from taking part in template deduction: optional("x", int_field, 0, 9).
template <typename T>
using NonDeduced = typename detail::NonDeducedT<T>::type;

// Parses YAML text; OpenCV's "%YAML:1.0" first line (which yaml-cpp rejects) is blanked out so
// line numbers stay right. Syntax errors and a second document become InputError(source, line, ...).
YAML::Node loadYamlString(const std::string& text, const std::string& source);
// Same for a file; a missing or unreadable file is an InputError naming it.
YAML::Node loadYamlFile(const std::string& path);

class YamlOptionsReader {
 public:
  // node must be a map; a null node (empty document, or `key:` with nothing) is an empty map.
  // source names the file in errors; prefix ("masker.") is prepended to key names in errors.
  YamlOptionsReader(const YAML::Node& node, std::string source, std::string prefix = "");
  static YamlOptionsReader fromFile(const std::string& path);
  static YamlOptionsReader fromString(const std::string& text, const std::string& source);

  bool has(const std::string& key) const;

  // Reads the key into value and returns true; returns false and leaves value alone when absent.
  // Supported T: bool, int, int64_t, double, float, std::string, std::vector<double|int|string>,
  // std::vector<std::vector<double>> (a matrix as a list of rows).
  template <typename T>
  bool optional(const std::string& key, T& value);
  // As above, then checks lo <= value <= hi (numbers only).
  template <typename T>
  bool optional(const std::string& key, T& value, NonDeduced<T> lo, NonDeduced<T> hi);
  // Throws InputError when the key is absent.
  template <typename T>
  void required(const std::string& key, T& value);
  template <typename T>
  void required(const std::string& key, T& value, NonDeduced<T> lo, NonDeduced<T> hi);

  // The reader of a nested map. Absent and not required: a reader over an empty map (defaults
  // kept). Call finish() on it as well.
  YamlOptionsReader child(const std::string& key, bool required = false);

  // Throws InputError for the first key that no optional/required/child call asked for.
  void finish() const;
  // The keys nobody asked for, with their prefix ("cam0.T_cn_cnm1"), in file order: what a reader
  // of another tool's file reports as ignored where the project's own files call finish().
  std::vector<std::string> unusedKeys() const;
  // The raw node of key (undefined when absent), for layouts the typed readers do not cover
  // (lists of maps); node() marks the key as asked for, peek() does not.
  YAML::Node node(const std::string& key);
  YAML::Node peek(const std::string& key) const;
  // The line of key in the file (the map's own line when the key is absent).
  long keyLine(const std::string& key) const;

  // Throws InputError naming the key (and its line) unless ok.
  void check(bool ok, const std::string& key, const std::string& what) const {
    if (!ok) fail(key, what);
  }
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  const std::string& source() const { return source_; }

 private:
  struct Entry {
    std::string key;
    YAML::Node value;
    long line = 0;
    bool used = false;
  };

  Entry* use(const std::string& key);
  const Entry* find(const std::string& key) const;
  [[noreturn]] void failAt(long line, const std::string& key, const std::string& what) const;
  template <typename T>
  void checkRange(const std::string& key, const T& value, const T& lo, const T& hi) const;

  // Strict converters (defined in the .cpp); they throw InputError naming the key and line.
  void convert(const Entry& e, bool& out) const;
  void convert(const Entry& e, int& out) const;
  void convert(const Entry& e, int64_t& out) const;
  void convert(const Entry& e, double& out) const;
  void convert(const Entry& e, float& out) const;
  void convert(const Entry& e, std::string& out) const;
  void convert(const Entry& e, std::vector<double>& out) const;
  void convert(const Entry& e, std::vector<int>& out) const;
  void convert(const Entry& e, std::vector<std::string>& out) const;
  void convert(const Entry& e, std::vector<std::vector<double>>& out) const;
  template <typename T>
  void convertScalar(const Entry& e, T& out) const;
  template <typename T>
  void convertList(const Entry& e, std::vector<T>& out) const;

  std::string source_;
  std::string prefix_;
  long line_ = 0;  // line of the map itself (for "missing key" errors)
  std::vector<Entry> entries_;
  std::vector<std::string> asked_;  // every key the caller asked for, for "known keys" in errors
};

// ---- template definitions ----

template <typename T>
bool YamlOptionsReader::optional(const std::string& key, T& value) {
  const Entry* e = use(key);
  if (!e) return false;
  convert(*e, value);
  return true;
}

template <typename T>
bool YamlOptionsReader::optional(const std::string& key, T& value, NonDeduced<T> lo,
                                 NonDeduced<T> hi) {
  T v = value;
  if (!optional(key, v)) return false;
  checkRange<T>(key, v, lo, hi);
  value = v;
  return true;
}

template <typename T>
void YamlOptionsReader::required(const std::string& key, T& value) {
  if (!optional(key, value)) failAt(line_, key, "missing required key");
}

template <typename T>
void YamlOptionsReader::required(const std::string& key, T& value, NonDeduced<T> lo,
                                 NonDeduced<T> hi) {
  if (!optional(key, value, lo, hi)) failAt(line_, key, "missing required key");
}

template <typename T>
void YamlOptionsReader::checkRange(const std::string& key, const T& value, const T& lo,
                                   const T& hi) const {
  static_assert(std::is_arithmetic_v<T>, "range checks are for numbers");
  if (value < lo || value > hi) {
    const Entry* e = find(key);
    failAt(e ? e->line : line_, key,
           "value " + detail::numberText(value) + " is out of range [" + detail::numberText(lo) +
               ", " + detail::numberText(hi) + "]");
  }
}

}  // namespace adugs::data
