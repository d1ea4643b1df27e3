#include "calib/target/aprilgrid_target_yaml.h"

#include <sstream>
#include <stdexcept>

#include "calib/text_format.h"
#include "data/formats/yaml_options.h"

namespace adugs::calib {
namespace {

// Reads one key given in either spelling; both spellings at once would be ambiguous.
template <typename T>
void readEither(data::YamlOptionsReader& r, const std::string& camel, const std::string& snake,
                T& value, T lo, T hi, bool required) {
  if (r.has(camel) && r.has(snake))
    r.fail(snake, "given twice (as '" + camel + "' and '" + snake + "'); keep one");
  if (r.optional(camel, value, lo, hi) || r.optional(snake, value, lo, hi)) return;
  if (required) r.required(camel, value, lo, hi);  // throws "missing required key"
}

AprilGrid readGrid(data::YamlOptionsReader& r) {
  std::string type;
  r.required("target_type", type);
  if (type == "checkerboard" || type == "circlegrid")
    r.fail("target_type", "'" + type + "' targets are not supported; use 'aprilgrid'");
  r.check(type == "aprilgrid", "target_type", "unknown target type '" + type + "'");
  AprilGrid g;
  readEither(r, "tagRows", "tag_rows", g.tag_rows, 1, 1000, true);
  readEither(r, "tagCols", "tag_cols", g.tag_cols, 1, 1000, true);
  readEither(r, "tagSize", "tag_size", g.tag_size_m, 1e-4, 100.0, true);
  readEither(r, "tagSpacing", "tag_spacing", g.tag_spacing, 0.0, 10.0, true);
  readEither(r, "borderBits", "border_bits", g.border_bits, 1, 2, false);
  r.check(g.numTags() <= kTag36h11Count, r.has("tagRows") ? "tagRows" : "tag_rows",
          "tagRows * tagCols = " + std::to_string(g.numTags()) + " exceeds the " +
              std::to_string(kTag36h11Count) + " tag36h11 codes");
  r.finish();
  try {
    g.validate();
  } catch (const std::invalid_argument& e) {
    r.fail("", e.what());
  }
  return g;
}

}  // namespace

AprilGrid readAprilGridYaml(const std::string& path) {
  auto r = data::YamlOptionsReader::fromFile(path);
  return readGrid(r);
}

AprilGrid parseAprilGridYaml(const std::string& text, const std::string& source) {
  auto r = data::YamlOptionsReader::fromString(text, source);
  return readGrid(r);
}

std::string formatAprilGridYaml(const AprilGrid& g) {
  std::ostringstream os;
  os << "target_type: 'aprilgrid'\n"
     << "tagRows: " << g.tag_rows << "\n"
     << "tagCols: " << g.tag_cols << "\n"
     << "tagSize: " << formatDouble(g.tag_size_m) << "        # edge of the black square [m]\n"
     << "tagSpacing: " << formatDouble(g.tag_spacing) << "     # gap between tags / tagSize\n";
  if (g.border_bits != 2) os << "borderBits: " << g.border_bits << "   # not a Kalibr key\n";
  return os.str();
}

}  // namespace adugs::calib
