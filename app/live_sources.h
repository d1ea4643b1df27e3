#pragma once
// The sources `adugs live` and `adugs record` read, chosen on the command line (exactly one):
//   --replay SEQ     a recorded sequence (any format `adugs run` reads, same options) delivered at
//                    sensor pace with a D435i's timing (data/sources/replay_source.h)
//   --video FILE     a video played as a live camera (data/sources/video_file_source.h), vision only
//   --v4l2 /dev/videoN   any V4L2 camera (data/sources/v4l2_camera_source.h), vision only
//   --d435i          a RealSense D435i without librealsense (data/sources/d435i_source.h): infrared
//                    images and IMU on the camera's clock; its options are the run config's d435i:
//                    map, its calibration --kalibr-camchain / --kalibr-imu or else the map's
//                    placeholder cam0 / imu0
// Vision-only sources take their camera from --kalibr-camchain, or else a guessed pinhole
// (fx = fy = image width, about 53 degrees across; principal point at the centre, no distortion),
// which the run summary says; tracking works with it, odometry needs a calibration.
#include <string>

#include <CLI/CLI.hpp>

#include "app/run_options.h"
#include "data/device/v4l2_io.h"
#include "data/sources/dataset_preset.h"
#include "data/sources/replay_source.h"
#include "data/sources/v4l2_camera_source.h"

namespace adugs::app {

struct LiveSourceArgs {
  SequenceArgs sequence;  // --replay's path and options; --kalibr-camchain for the cameras too
  std::string replay, video, v4l2;
  bool d435i = false;
  data::ReplayTiming replay_timing;
  double video_speed = 1;
  std::string v4l2_size;  // WxH
  data::V4l2Request v4l2_request;
};

void addLiveSourceOptions(CLI::App* cmd, LiveSourceArgs& args);

// Opens the source asked for (InputError when none or several are given). out_dir: where a bag's
// ground truth is written (as `adugs run` does). device_io: the system calls the D435i source
// makes (the tests give a fake kernel layer).
data::OpenedSequence openLiveSource(const LiveSourceArgs& args, const std::string& config_path,
                                    const std::string& out_dir, data::V4l2Io& device_io = data::systemV4l2Io());

// The camera of a vision-only source: cam0 of the calibration files (its resolution must match;
// an IMU in them is an error) or guessed.
data::CameraCalibration visionOnlyCamera(int width, int height, double rate_hz,
                                         const std::vector<std::string>& calibration, std::string* from);

}  // namespace adugs::app
