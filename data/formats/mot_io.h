#pragma once
// MOTChallenge box files (the simulator's objects0/gt.txt, tracker outputs):
//   frame,id,bb_left,bb_top,bb_width,bb_height,conf[,class,visibility][,...]
// frame is 1-based, bb_left/bb_top are 1-based pixel coordinates of the top-left pixel. Rows with
// 7 columns (tracker output) get class -1 and visibility 1.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace adugs::data {

struct MotBox {
  int frame = 0;
  int64_t id = 0;
  double left = 0, top = 0, width = 0, height = 0;  // 0-based (OpenCV) pixel coordinates
  double confidence = 1;
  int class_id = -1;
  double visibility = 1;
  double centerX() const { return left + width / 2; }
  double centerY() const { return top + height / 2; }
};

// frame -> its boxes. Throws InputError naming file, line and field for malformed rows,
// non-positive frame numbers or sizes, visibility outside [0, 1].
std::map<int, std::vector<MotBox>> readMotFile(const std::string& path);

}  // namespace adugs::data
