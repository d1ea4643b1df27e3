#include "data/formats/mot_io.h"

#include "data/formats/csv_reader.h"

namespace adugs::data {

std::map<int, std::vector<MotBox>> readMotFile(const std::string& path) {
  CsvReader csv(path);
  csv.setColumnNames(
      {"frame", "id", "bb_left", "bb_top", "bb_width", "bb_height", "conf", "class", "visibility"});
  std::map<int, std::vector<MotBox>> frames;
  while (csv.next()) {
    csv.requireColumns(7, 10);  // MOT16 gt has 9, MOT15 results 10 (x, y, z = -1)
    MotBox b;
    const int64_t frame = csv.int64At(0);
    if (frame < 1) csv.fail(0, "frame numbers are 1-based");
    b.frame = static_cast<int>(frame);
    b.id = csv.int64At(1);
    b.left = csv.doubleAt(2) - 1;
    b.top = csv.doubleAt(3) - 1;
    b.width = csv.doubleAt(4);
    b.height = csv.doubleAt(5);
    if (b.width <= 0) csv.fail(4, "box width must be positive");
    if (b.height <= 0) csv.fail(5, "box height must be positive");
    b.confidence = csv.doubleAt(6);
    if (csv.size() == 9) {  // MOT16/17 ground truth: class and visibility
      b.class_id = static_cast<int>(csv.int64At(7));
      b.visibility = csv.doubleAt(8);
      if (b.visibility < 0 || b.visibility > 1) csv.fail(8, "visibility must lie in [0, 1]");
    }
    frames[b.frame].push_back(b);
  }
  return frames;
}

}  // namespace adugs::data
