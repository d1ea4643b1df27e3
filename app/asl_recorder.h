#pragma once
// What `adugs record` does with an opened live source: writes it into an EuRoC ASL folder
// (data/formats/asl_writer.h: cam0 images, united IMU, sensor.yaml files) that `adugs run`, `adugs calib ...`
// and `adugs track` read back, and OUT/record.yaml.
//
// No acquired frame may be lost: the source is read on its own thread and handed to a writer thread
// through a queue that holds up to max_queued_frames frames (PNG encoding or a slow disk may lag
// behind for that long); if it overflows, the frame is counted as lost and the recording fails at
// the end. At the end the folder is checked: rows of cam0/data.csv and images on disk = frames
// acquired, rows of imu0/data.csv = IMU samples acquired. Ctrl-C (SIGINT/SIGTERM), the end of the
// source (--duration, a camera unplugged: record.yaml's end_detail says why) end the recording
// cleanly; everything acquired until then is written.
#include <string>

#include "data/sources/dataset_preset.h"

namespace adugs::app {

struct AslRecordOptions {
  std::string out_dir;  // gets mav0/ and record.yaml
  int max_queued_frames = 300;
  bool quiet = false;   // no progress line on stderr
};

// Records until the source ends or Ctrl-C; throws (after record.yaml is written) when the
// recording is incomplete or the source failed.
void recordToAsl(data::OpenedSequence& sequence, const AslRecordOptions& options);

}  // namespace adugs::app
