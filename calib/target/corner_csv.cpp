#include "calib/target/corner_csv.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "calib/text_format.h"
#include "data/formats/atomic_file.h"
#include "data/formats/csv_reader.h"
#include "data/input_error.h"

namespace adugs::calib {
namespace fs = std::filesystem;

TargetObservation readCornerCsv(const std::string& path, const AprilGrid* grid,
                                AprilGrid* grid_out) {
  data::CsvReader csv(path);
  csv.setColumnNames({"ts", "tag_rows", "tag_cols", "tag_size", "tag_spacing", "kp_x", "kp_y",
                      "p_x", "p_y", "p_z", "tag_id", "corner_idx"});
  TargetObservation obs;
  obs.source = path;
  AprilGrid g = grid ? *grid : AprilGrid{};
  bool have_grid = grid != nullptr;
  bool first = true;
  while (csv.next()) {
    csv.requireColumns(12);
    const int64_t ts = csv.int64At(0);
    const int64_t rows = csv.int64At(1), cols = csv.int64At(2);
    const double size = csv.doubleAt(3), spacing = csv.doubleAt(4);
    if (!have_grid) {
      if (rows < 1 || rows > 1000) csv.fail(1, "tag_rows must be 1..1000");
      if (cols < 1 || cols > 1000) csv.fail(2, "tag_cols must be 1..1000");
      g.tag_rows = static_cast<int>(rows);
      g.tag_cols = static_cast<int>(cols);
      g.tag_size_m = size;
      g.tag_spacing = spacing;
      try {
        g.validate();
      } catch (const std::exception& e) {
        csv.failRow(e.what());
      }
      have_grid = true;
    }
    if (rows != g.tag_rows) csv.fail(1, "does not match the target's tagRows " + std::to_string(g.tag_rows));
    if (cols != g.tag_cols) csv.fail(2, "does not match the target's tagCols " + std::to_string(g.tag_cols));
    // The files print 6 decimals.
    if (std::abs(size - g.tag_size_m) > 1e-6 * std::max(1.0, g.tag_size_m))
      csv.fail(3, "does not match the target's tagSize " + formatDouble(g.tag_size_m));
    if (std::abs(spacing - g.tag_spacing) > 1e-6)
      csv.fail(4, "does not match the target's tagSpacing " + formatDouble(g.tag_spacing));
    if (first) {
      obs.t_ns = ts;
      first = false;
    } else if (ts != obs.t_ns) {
      csv.fail(0, "timestamp differs from the file's first row (" + std::to_string(obs.t_ns) +
                      "); one file holds one image");
    }
    CornerObservation c;
    const int64_t id = csv.int64At(10), k = csv.int64At(11);
    if (id < 0 || id >= g.numTags()) csv.fail(10, "tag id outside 0.." + std::to_string(g.numTags() - 1));
    if (k < 0 || k > 3) csv.fail(11, "corner index outside 0..3");
    c.tag_id = static_cast<int>(id);
    c.corner = static_cast<int>(k);
    c.pixel = {csv.doubleAt(5), csv.doubleAt(6)};
    c.point = {csv.doubleAt(7), csv.doubleAt(8), csv.doubleAt(9)};
    if ((c.point - g.corner(c.tag_id, c.corner)).norm() > 1e-5)
      csv.fail(7, "point is not corner " + std::to_string(k) + " of tag " + std::to_string(id) +
                      " of the target");
    obs.corners.push_back(c);
  }
  if (grid_out && have_grid) *grid_out = g;
  return obs;
}

std::vector<TargetObservation> readCornerCsvs(const std::string& path, const AprilGrid* grid,
                                              AprilGrid* grid_out) {
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    for (const auto& e : fs::directory_iterator(path))
      if (e.is_regular_file() && e.path().extension() == ".csv") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw data::InputError(path, 0, "", "no *.csv corner files in this folder");
  } else if (fs::is_regular_file(path, ec)) {
    files.push_back(path);
  } else {
    throw data::InputError(path, 0, "", "no such corner CSV file or folder");
  }
  std::vector<TargetObservation> out;
  AprilGrid g;
  const AprilGrid* use = grid;
  for (const auto& f : files) {
    AprilGrid read;
    bool had = use != nullptr;
    out.push_back(readCornerCsv(f, use, &read));
    if (!had && !out.back().corners.empty()) {
      g = read;
      use = &g;
    }
  }
  if (grid_out && use) *grid_out = *use;
  return out;
}

std::string formatCornerCsv(const AprilGrid& g, const TargetObservation& obs) {
  std::string s = "#ts,tag_rows,tag_cols,tag_size,tag_spacing,kp_x,kp_y,p_x,p_y,p_z,tag_id,corner_idx\n";
  for (const auto& c : obs.corners)
    s += strprintf("%lld,%d,%d,%f,%f,%.10f,%.10f,%f,%f,%f,%d,%d\n",
                   static_cast<long long>(obs.t_ns), g.tag_rows, g.tag_cols, g.tag_size_m,
                   g.tag_spacing, c.pixel.x(), c.pixel.y(), c.point.x(), c.point.y(), c.point.z(),
                   c.tag_id, c.corner);
  return s;
}

void writeCornerCsv(const std::string& path, const AprilGrid& grid, const TargetObservation& obs) {
  data::writeTextFileAtomically(path, formatCornerCsv(grid, obs));
}

}  // namespace adugs::calib
