#pragma once
// The sources `adugs live` and `adugs record` read, chosen on the command line (exactly one):
//   --replay SEQ     a recorded sequence (any format `adugs run` reads, same options) delivered at
//                    sensor pace with a D435i's timing (app/live/replay_source.h)
//   --video FILE     a video played as a live camera (app/live/video_file_source.h), vision only
//   --v4l2 /dev/videoN   any V4L2 camera (app/live/v4l2_camera_source.h), vision only
// Vision-only sources take their camera from --kalibr-camchain, or else a guessed pinhole
// (fx = fy = image width, about 53 degrees across; principal point at the centre, no distortion),
// which the run summary says; tracking works with it, odometry needs a calibration.
#include <string>

#include <CLI/CLI.hpp>

#include "app/live/replay_source.h"
#include "app/live/v4l2_camera_source.h"
#include "app/run_options.h"
#include "data/dataset_preset.h"

namespace adugs::app {

struct LiveSourceArgs {
  SequenceArgs sequence;  // --replay's path and options; --kalibr-camchain for the cameras too
  std::string replay, video, v4l2;
  ReplayTiming replay_timing;
  double video_speed = 1;
  std::string v4l2_size;  // WxH
  V4l2Request v4l2_request;
};

void addLiveSourceOptions(CLI::App* cmd, LiveSourceArgs& args);

// Opens the source asked for (InputError when none or several are given). out_dir: where a bag's
// ground truth is written (as `adugs run` does).
data::OpenedSequence openLiveSource(const LiveSourceArgs& args, const std::string& config_path,
                                    const std::string& out_dir);

// The camera of a vision-only source: from a Kalibr camchain (its resolution must match) or guessed.
data::CameraCalibration visionOnlyCamera(int width, int height, double rate_hz, const std::string& kalibr_camchain,
                                         std::string* from);

}  // namespace adugs::app
