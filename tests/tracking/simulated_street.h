#pragma once
// A short simulated street sequence (level high, seed 3) with its object ground truth, for the
// tracking tests and benchmarks: images, exact dynamic masks and MOT boxes per frame.
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "data/formats/mot_io.h"
#include "data/sim/sim_sequence.h"
#include "tracking/box.h"

namespace adugs::tracking::test_support {

struct SimulatedStreet {
  std::filesystem::path root;
  std::vector<std::string> image_names;            // cam0 data.csv order (frame k = index k-1)
  std::map<int, std::vector<data::MotBox>> boxes;  // 1-based frame -> ground-truth boxes

  std::string imagePath(int frame) const {
    return (root / "mav0/cam0/data" / image_names.at(frame - 1)).string();
  }
  std::string maskPath(int frame) const {
    return (root / "mav0/mask0/data" / image_names.at(frame - 1)).string();
  }
  // Boxes of a frame whose visible fraction exceeds min_visibility.
  std::vector<Box> visibleBoxes(int frame, double min_visibility) const {
    std::vector<Box> out;
    const auto it = boxes.find(frame);
    if (it == boxes.end()) return out;
    for (const data::MotBox& b : it->second)
      if (b.visibility > min_visibility)
        out.push_back(Box{b.centerX(), b.centerY(), b.width, b.height});
    return out;
  }
};

inline SimulatedStreet makeSimulatedStreet(const std::filesystem::path& dir, double duration_s) {
  data::SimSequenceOptions o;
  o.scene = "street";
  o.level = data::SimLevel::kHigh;
  o.seed = 3;
  o.duration_s = duration_s;
  o.progress = false;
  data::generateSimSequence(o, dir.string());
  SimulatedStreet s;
  s.root = dir;
  s.boxes = data::readMotFile((dir / "mav0/objects0/gt.txt").string());
  std::ifstream csv(dir / "mav0/cam0/data.csv");
  std::string line;
  std::getline(csv, line);  // header
  while (std::getline(csv, line))
    if (!line.empty()) s.image_names.push_back(line.substr(line.find(',') + 1));
  return s;
}

}  // namespace adugs::tracking::test_support
