#pragma once
// Kalibr-style target YAML for an AprilGrid:
//   target_type: 'aprilgrid'
//   tagRows: 6      tagCols: 6      tagSize: 0.088      tagSpacing: 0.3
// The snake_case spelling of yac/EuRoC (tag_rows, tag_cols, tag_size, tag_spacing) is accepted
// too, but not both spellings of one key. Optional (ours): borderBits / border_bits (default 2,
// as Kalibr prints). Unknown keys, missing keys and bad values are InputError naming file/line.
#include <string>

#include "calib/target/aprilgrid.h"

namespace adugs::calib {

AprilGrid readAprilGridYaml(const std::string& path);
AprilGrid parseAprilGridYaml(const std::string& text, const std::string& source);

// Kalibr spelling, readable by Kalibr and by readAprilGridYaml.
std::string formatAprilGridYaml(const AprilGrid& grid);

}  // namespace adugs::calib
