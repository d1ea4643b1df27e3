#include "data/formats/yaml_options.h"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <yaml-cpp/eventhandler.h>

#include "data/formats/csv_reader.h"  // parseInt64, parseDouble
#include "data/input_error.h"

namespace adugs::data {
namespace {

long lineOf(const YAML::Node& n, long fallback = 0) {
  if (!n.IsDefined()) return fallback;
  YAML::Mark m = n.Mark();
  return m.is_null() ? fallback : static_cast<long>(m.line) + 1;
}

std::string kindOf(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null: return "no value";
    case YAML::NodeType::Scalar: return "a single value";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Map: return "a map";
    default: return "nothing";
  }
}

// YAML's own spellings of non-finite numbers (.inf, -.Inf, .NaN, ...).
bool isYamlNonFinite(std::string s) {
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.erase(0, 1);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s == ".inf" || s == ".nan";
}

// Parser events, ignored except for where the second document starts.
struct DocumentStarts : YAML::EventHandler {
  int documents = 0;
  long second_line = 0;
  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents == 2) second_line = mark.is_null() ? 0 : mark.line + 1;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

// Scalar converters: "" on success, otherwise what is wrong.
std::string toValue(const YAML::Node& n, std::string& out) {
  if (!n.IsScalar()) return "expected a single value, found " + kindOf(n);
  out = n.Scalar();
  return "";
}

std::string toValue(const YAML::Node& n, double& out) {
  std::string s;
  if (!toValue(n, s).empty()) return "expected a number, found " + kindOf(n);
  if (isYamlNonFinite(s)) return "value is not finite: '" + s + "'";
  bool overflow = false;
  double v = 0;
  if (!parseDouble(s, v, &overflow)) {
    return overflow ? "number out of range: '" + s + "'" : "expected a number, found '" + s + "'";
  }
  if (!std::isfinite(v)) return "value is not finite: '" + s + "'";
  out = v;
  return "";
}

std::string toValue(const YAML::Node& n, float& out) {
  double v = 0;
  std::string err = toValue(n, v);
  if (!err.empty()) return err;
  if (std::fabs(v) > FLT_MAX) return "number out of range for float: '" + n.Scalar() + "'";
  out = static_cast<float>(v);
  return "";
}

std::string toValue(const YAML::Node& n, int64_t& out) {
  std::string s;
  if (!toValue(n, s).empty()) return "expected an integer, found " + kindOf(n);
  bool overflow = false;
  if (!parseInt64(s, out, &overflow)) {
    return overflow ? "integer out of range: '" + s + "'" : "expected an integer, found '" + s + "'";
  }
  return "";
}

std::string toValue(const YAML::Node& n, int& out) {
  int64_t v = 0;
  std::string err = toValue(n, v);
  if (!err.empty()) return err;
  if (v < INT_MIN || v > INT_MAX) return "integer out of range: '" + n.Scalar() + "'";
  out = static_cast<int>(v);
  return "";
}

std::string toValue(const YAML::Node& n, bool& out) {
  std::string s;
  if (!toValue(n, s).empty()) return "expected true or false, found " + kindOf(n);
  if (s == "true" || s == "True" || s == "TRUE") {
    out = true;
  } else if (s == "false" || s == "False" || s == "FALSE") {
    out = false;
  } else {
    return "expected true or false, found '" + s + "'";
  }
  return "";
}

}  // namespace

YAML::Node loadYamlString(const std::string& text, const std::string& source) {
  std::string body = text;
  if (body.rfind("%YAML:", 0) == 0) body.erase(0, body.find('\n'));  // keep the '\n': same lines
  try {
    // Not YAML::LoadAll: yaml-cpp 0.7 loops forever (allocating) on a stray ',' at document level,
    // yielding empty documents without consuming it (found by tests/fuzz/fuzz_yaml).
    std::istringstream in(body);
    YAML::Parser parser(in);
    DocumentStarts starts;
    if (parser.HandleNextDocument(starts) && parser.HandleNextDocument(starts)) {
      throw InputError(source, starts.second_line, "",
                       "unexpected content after the first YAML document (a second '---' document or a "
                       "stray character)");
    }
    return YAML::Load(body);
  } catch (const YAML::Exception& e) {
    throw InputError(source, e.mark.is_null() ? 0 : e.mark.line + 1, "", "YAML syntax error: " + e.msg);
  }
}

YAML::Node loadYamlFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, 0, "", "is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "", "read error");
  return loadYamlString(text.str(), path);
}

YamlOptionsReader::YamlOptionsReader(const YAML::Node& node, std::string source, std::string prefix)
    : source_(std::move(source)), prefix_(std::move(prefix)), line_(lineOf(node)) {
  if (!node.IsDefined() || node.IsNull()) return;
  std::string self = prefix_.empty() ? "" : prefix_.substr(0, prefix_.size() - 1);
  if (!node.IsMap()) throw InputError(source_, line_, self, "expected a map of 'key: value', found " + kindOf(node));
  for (auto it = node.begin(); it != node.end(); ++it) {
    long line = lineOf(it->first, line_);
    if (!it->first.IsScalar()) throw InputError(source_, line, self, "a key must be a plain name");
    std::string key = it->first.Scalar();
    if (const Entry* first = find(key)) {
      failAt(line, key, "duplicate key (first on line " + std::to_string(first->line) + ")");
    }
    entries_.push_back(Entry{key, it->second, line, false});
  }
}

YamlOptionsReader YamlOptionsReader::fromFile(const std::string& path) {
  return YamlOptionsReader(loadYamlFile(path), path);
}

YamlOptionsReader YamlOptionsReader::fromString(const std::string& text, const std::string& source) {
  return YamlOptionsReader(loadYamlString(text, source), source);
}

bool YamlOptionsReader::has(const std::string& key) const { return find(key) != nullptr; }

const YamlOptionsReader::Entry* YamlOptionsReader::find(const std::string& key) const {
  for (const Entry& e : entries_) {
    if (e.key == key) return &e;
  }
  return nullptr;
}

YamlOptionsReader::Entry* YamlOptionsReader::use(const std::string& key) {
  if (std::find(asked_.begin(), asked_.end(), key) == asked_.end()) asked_.push_back(key);
  for (Entry& e : entries_) {
    if (e.key == key) {
      e.used = true;
      return &e;
    }
  }
  return nullptr;
}

YamlOptionsReader YamlOptionsReader::child(const std::string& key, bool required) {
  const Entry* e = use(key);
  if (!e) {
    if (required) failAt(line_, key, "missing required key");
    return YamlOptionsReader(YAML::Node(), source_, prefix_ + key + ".");
  }
  if (!e->value.IsMap() && !e->value.IsNull()) failAt(e->line, key, "expected a map, found " + kindOf(e->value));
  YamlOptionsReader r(e->value, source_, prefix_ + key + ".");
  if (r.line_ == 0) r.line_ = e->line;
  return r;
}

void YamlOptionsReader::finish() const {
  for (const Entry& e : entries_) {
    if (e.used) continue;
    std::string known;
    for (const std::string& k : asked_) known += (known.empty() ? "" : ", ") + k;
    failAt(e.line, e.key, known.empty() ? "unknown key" : "unknown key (known keys: " + known + ")");
  }
}

std::vector<std::string> YamlOptionsReader::unusedKeys() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_)
    if (!e.used) out.push_back(prefix_ + e.key);
  return out;
}

YAML::Node YamlOptionsReader::node(const std::string& key) {
  const Entry* e = use(key);
  return e ? e->value : YAML::Node(YAML::NodeType::Undefined);
}

YAML::Node YamlOptionsReader::peek(const std::string& key) const {
  const Entry* e = find(key);
  return e ? e->value : YAML::Node(YAML::NodeType::Undefined);
}

long YamlOptionsReader::keyLine(const std::string& key) const {
  const Entry* e = find(key);
  return e ? e->line : line_;
}

void YamlOptionsReader::fail(const std::string& key, const std::string& what) const {
  const Entry* e = find(key);
  failAt(e ? e->line : line_, key, what);
}

void YamlOptionsReader::failAt(long line, const std::string& key, const std::string& what) const {
  throw InputError(source_, line, prefix_ + key, what);
}

template <typename T>
void YamlOptionsReader::convertScalar(const Entry& e, T& out) const {
  std::string err = toValue(e.value, out);
  if (!err.empty()) failAt(e.line, e.key, err);
}

template <typename T>
void YamlOptionsReader::convertList(const Entry& e, std::vector<T>& out) const {
  if (!e.value.IsSequence()) failAt(e.line, e.key, "expected a list [a, b, ...], found " + kindOf(e.value));
  std::vector<T> values;
  for (const YAML::Node& item : e.value) {
    T v{};
    std::string err = toValue(item, v);
    if (!err.empty()) {
      failAt(lineOf(item, e.line), e.key + "[" + std::to_string(values.size()) + "]", err);
    }
    values.push_back(v);
  }
  out = std::move(values);
}

void YamlOptionsReader::convert(const Entry& e, bool& out) const { convertScalar(e, out); }
void YamlOptionsReader::convert(const Entry& e, int& out) const { convertScalar(e, out); }
void YamlOptionsReader::convert(const Entry& e, int64_t& out) const { convertScalar(e, out); }
void YamlOptionsReader::convert(const Entry& e, double& out) const { convertScalar(e, out); }
void YamlOptionsReader::convert(const Entry& e, float& out) const { convertScalar(e, out); }
void YamlOptionsReader::convert(const Entry& e, std::string& out) const { convertScalar(e, out); }
void YamlOptionsReader::convert(const Entry& e, std::vector<double>& out) const { convertList(e, out); }
void YamlOptionsReader::convert(const Entry& e, std::vector<int>& out) const { convertList(e, out); }
void YamlOptionsReader::convert(const Entry& e, std::vector<std::string>& out) const {
  convertList(e, out);
}
void YamlOptionsReader::convert(const Entry& e, std::vector<std::vector<double>>& out) const {
  if (!e.value.IsSequence()) failAt(e.line, e.key, "expected a list of rows [[a, b], ...], found " + kindOf(e.value));
  std::vector<std::vector<double>> rows;
  for (const YAML::Node& row : e.value) {
    const std::string name = e.key + "[" + std::to_string(rows.size()) + "]";
    if (!row.IsSequence()) failAt(lineOf(row, e.line), name, "expected a row [a, b, ...], found " + kindOf(row));
    Entry row_entry{name, row, lineOf(row, e.line), true};
    rows.emplace_back();
    convertList(row_entry, rows.back());
  }
  out = std::move(rows);
}

}  // namespace adugs::data
