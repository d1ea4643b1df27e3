#include "data/sim/sim_sequence_writer.h"

#include <cstdio>
#include <filesystem>


#include "data/formats/atomic_file.h"
#include "data/input_error.h"

namespace adugs::data {

namespace fs = std::filesystem;

std::string formatMotRow(int frame, const SimObjectBox& b) {
  char buf[160];
  // conf 0 for a standing object: MOTChallenge's "ignore" flag (as its static people), neither a
  // target nor a false positive for eval-mot, and not a mover for the per-class recall.
  std::snprintf(buf, sizeof buf, "%d,%d,%d,%d,%d,%d,%d,%d,%.4f", frame, b.id, b.box.x + 1, b.box.y + 1,
                b.box.width, b.box.height, b.moving ? 1 : 0, cocoClassId(b.cls), b.visibility());
  return buf;
}

SimSequenceWriter::SimSequenceWriter(const std::string& root, const CameraCalibration& camera,
                                     const ImuNoise& imu)
    : asl_(root, camera, &imu, /*masks=*/true) {
  const fs::path objects = fs::path(asl_.mavDir()) / "objects0";
  std::error_code ec;
  fs::create_directories(objects, ec);
  if (ec) throw InputError(objects.string(), 0, "", "cannot create folder: " + ec.message());
  mot_.open(objects / "gt.txt", std::ios::binary | std::ios::trunc);
  if (!mot_) throw InputError((objects / "gt.txt").string(), 0, "", "cannot open for writing");
  mot_ << "# frame,id,bb_left,bb_top,bb_width,bb_height,conf,class,visibility\n";
  mot_.flush();
}

void SimSequenceWriter::writeImu(const std::vector<ImuSample>& samples) {
  for (const ImuSample& m : samples) asl_.writeImu(m);
  asl_.flush();
}

void SimSequenceWriter::writeGroundTruth(const std::vector<GroundTruthState>& states) {
  asl_.writeGroundTruth(states);
}

void SimSequenceWriter::writeInfo(const std::string& yaml_text) {
  writeTextFileAtomically((fs::path(asl_.mavDir()) / "sim.yaml").string(), yaml_text);
}

void SimSequenceWriter::writeFrame(int64_t t_ns, const SimFrame& frame) {
  asl_.writeFrame(t_ns, frame.image, frame.mask);
  for (const SimObjectBox& b : frame.boxes) mot_ << formatMotRow(asl_.framesWritten(), b) << "\n";
  mot_.flush();
  if (!mot_) throw InputError(asl_.mavDir() + "/objects0/gt.txt", 0, "", "cannot write");
}

}  // namespace adugs::data
