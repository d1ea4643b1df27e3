#pragma once
// Writes a simulated sequence as an EuRoC ASL folder plus dynamic-object ground truth:
//   mav0/cam0/data/<t>.png, data.csv, sensor.yaml          images (8-bit grey)
//   mav0/mask0/data/<t>.png, data.csv                      dynamic masks (255 = moving object)
//   mav0/imu0/data.csv, sensor.yaml                        IMU (EuRoC columns)
//   mav0/state_groundtruth_estimate0/data.csv              pose, velocity, biases (qw first)
//   mav0/objects0/gt.txt                                   MOTChallenge CSV, one row per object
//                                                          per frame (frame = 1-based row in
//                                                          cam0/data.csv)
// The ASL part is data/formats/asl_writer.h's (images written to a temporary name and renamed, CSV rows
// flushed after their image, so a killed run leaves a consistent, shorter sequence); this class
// adds the object ground truth and sim.yaml.
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "data/formats/asl_writer.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/sim/sim_renderer.h"
#include "data/types.h"

namespace adugs::data {

class SimSequenceWriter {
 public:
  // Creates the folders under root (root/mav0/...) and writes both sensor.yaml files.
  // Throws InputError if a folder or file cannot be created.
  SimSequenceWriter(const std::string& root, const CameraCalibration& camera, const ImuNoise& imu);

  // Whole files: the IMU rows (flushed), the ground truth (atomically).
  void writeImu(const std::vector<ImuSample>& samples);
  void writeGroundTruth(const std::vector<GroundTruthState>& states);
  // Free-form description of how the sequence was made (mav0/sim.yaml).
  void writeInfo(const std::string& yaml_text);

  // One frame: image, mask, CSV rows, MOT rows. Frames must come in increasing time.
  void writeFrame(int64_t t_ns, const SimFrame& frame);

  int framesWritten() const { return asl_.framesWritten(); }
  const std::string& mavDir() const { return asl_.mavDir(); }

 private:
  AslWriter asl_;
  std::ofstream mot_;
};

// "frame,id,bb_left,bb_top,bb_width,bb_height,conf,class,visibility" (no newline). bb_left/bb_top
// are 1-based pixel coordinates as in MOTChallenge; class is the COCO id; visibility the visible
// fraction; conf is 1 for a moving object, 0 (MOTChallenge: ignore) for a standing one.
std::string formatMotRow(int frame, const SimObjectBox& box);

}  // namespace adugs::data
