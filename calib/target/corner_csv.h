#pragma once
// AprilGrid corner detections as CSV, the format of yac / the EuRoC calibration detections:
//   #ts,tag_rows,tag_cols,tag_size,tag_spacing,kp_x,kp_y,p_x,p_y,p_z,tag_id,corner_idx
// one file per image (all rows carry that image's timestamp in ns). Reading checks every row
// against the grid: the grid columns must agree with it and p must be corner(tag_id,
// corner_idx) of it; a disagreement is an InputError naming the file, line and column.
#include <string>
#include <vector>

#include "calib/target/aprilgrid.h"
#include "calib/target/target_observation.h"

namespace adugs::calib {

// Reads one CSV file. If grid is null, the grid is taken from the first row (and stored in
// *grid_out when given); every later row must agree. An empty file gives no corners.
TargetObservation readCornerCsv(const std::string& path, const AprilGrid* grid,
                                AprilGrid* grid_out = nullptr);

// Reads every *.csv in a folder (sorted by name), or a single file. Views without corners are
// kept (with source set) so the caller can count them.
std::vector<TargetObservation> readCornerCsvs(const std::string& path, const AprilGrid* grid,
                                              AprilGrid* grid_out = nullptr);

std::string formatCornerCsv(const AprilGrid& grid, const TargetObservation& obs);
void writeCornerCsv(const std::string& path, const AprilGrid& grid, const TargetObservation& obs);

}  // namespace adugs::calib
