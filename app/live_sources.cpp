#include "app/live_sources.h"

#include <iostream>
#include <memory>

#include "app/run_config.h"
#include "data/formats/calibration_files.h"
#include "data/input_error.h"
#include "data/sources/d435i_source.h"
#include "data/sources/playback_controls.h"
#include "data/sources/video_file_source.h"

namespace adugs::app {
namespace {

// --start / --duration on a camera: measured from its first measurement.
data::OpenedSequence withStartAndDuration(data::OpenedSequence s, const SequenceArgs& args) {
  const int64_t start = data::secToNs(args.start_s), duration = data::secToNs(args.duration_s);
  if (start > 0 || duration > 0)
    s.source = std::make_unique<data::PlaybackControls>(std::move(s.source), start, duration, false);
  return s;
}

}  // namespace

void addLiveSourceOptions(CLI::App* cmd, LiveSourceArgs& a) {
  cmd->add_option("--replay", a.replay,
                  "a recorded sequence (folder or ROS1 bag, as adugs run reads them) delivered at sensor pace with a "
                  "D435i's timing: the live path without a camera");
  cmd->add_option("--video", a.video,
                  "a video file (or a folder of images) played as a live camera (vision only: masking and tracking)")
      ->check(CLI::ExistingPath);
  cmd->add_option("--v4l2", a.v4l2, "a V4L2 camera, e.g. /dev/video0 (vision only: masking and tracking)");
  cmd->add_flag("--d435i", a.d435i,
                "a RealSense D435i without librealsense (infrared + IMU on the camera's clock; options: the --config's "
                "d435i: map, e.g. data/config/d435i.yaml; see doc/d435i.md)");
  addSequenceOptions(cmd, a.sequence);
  data::ReplayTiming& t = a.replay_timing;
  cmd->add_option("--replay-speed", t.speed, "--replay: sensor seconds per wall second")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->add_option("--replay-latency-ms", t.frame_latency_ms, "--replay: frames arrive this long after their stamp")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  cmd->add_option("--replay-jitter-ms", t.frame_jitter_ms, "--replay: +- this much on the frame latency (uniform)")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  cmd->add_option("--replay-frame-loss", t.frame_loss, "--replay: fraction of frames lost on the way")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  cmd->add_option("--replay-imu-burst-ms", t.imu_burst_ms, "--replay: IMU samples arrive in packets this often")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  cmd->add_option("--replay-seed", t.seed, "--replay: seed of the lost frames and the jitter")->capture_default_str();
  cmd->add_option("--speed", a.video_speed, "--video: play at this many times the video's rate")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->add_option("--v4l2-size", a.v4l2_size, "--v4l2: WxH to ask the camera for, e.g. 640x480");
  cmd->add_option("--v4l2-fps", a.v4l2_request.fps, "--v4l2: frame rate to ask the camera for")->check(CLI::Range(1.0, 1000.0));
  cmd->add_option("--v4l2-format", a.v4l2_request.fourcc, "--v4l2: pixel format to ask for (MJPG, YUYV, GREY, ...)");
}

data::CameraCalibration visionOnlyCamera(int width, int height, double rate_hz,
                                         const std::vector<std::string>& calibration, std::string* from) {
  if (!calibration.empty()) {
    const data::RigCalibration rig = data::readCalibrationFiles(calibration);
    data::reportIgnoredKeys(rig, std::cerr);
    if (rig.has_imu)
      throw data::InputError(rig.imu.source, 0, "--calibration", "--video and --v4l2 have no IMU (vision only): give the camera's file alone");
    if (rig.cameras.empty())
      throw data::InputError(calibration.front(), 0, "--calibration", "no camera in the calibration files");
    data::CameraCalibration c = rig.cameras.front().camera;
    if (c.width != width || c.height != height)
      throw data::InputError(rig.cameras.front().source, 0, "resolution",
                             "is " + std::to_string(c.width) + "x" + std::to_string(c.height) + ", the camera gives " +
                                 std::to_string(width) + "x" + std::to_string(height));
    if (c.rate_hz <= 0) c.rate_hz = rate_hz;
    *from = rig.formats.front() + " " + rig.cameras.front().source;
    return c;
  }
  data::CameraCalibration c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = width;
  c.cx = 0.5 * (width - 1);
  c.cy = 0.5 * (height - 1);
  c.distortion = {0, 0, 0, 0};
  c.rate_hz = rate_hz;
  *from = "none: a guessed pinhole (fx = fy = image width, centred, no distortion); give --calibration";
  return c;
}

data::OpenedSequence openLiveSource(const LiveSourceArgs& a, const std::string& config_path, const std::string& out_dir,
                                    data::V4l2Io& device_io) {
  const int given = !a.replay.empty() + !a.video.empty() + !a.v4l2.empty() + a.d435i;
  if (given != 1)
    throw data::InputError("command line", 0, "source",
                           given == 0 ? "give a source: --replay SEQ, --video FILE, --v4l2 /dev/videoN or --d435i"
                                      : "give one source only (--replay, --video, --v4l2 or --d435i)");
  const data::PlaybackOptions& p = a.sequence.playback;
  if (!a.replay.empty()) {
    data::PlaybackOptions playback = playbackOptions(a.sequence, config_path);
    playback.path = a.replay;
    data::OpenedSequence s = data::openSequence(playback, out_dir);
    s.source = std::make_unique<data::ReplaySource>(std::move(s.source), a.replay_timing);
    return s;
  }
  data::OpenedSequence s;
  if (a.d435i) {
    s = data::openD435i(loadRunConfig(config_path).d435i, p.calibration, device_io);
    return withStartAndDuration(std::move(s), a.sequence);
  }
  s.has_imu = false;
  s.calibration_files = p.calibration;
  if (!a.video.empty()) {
    auto video = std::make_unique<data::VideoFileSource>(a.video, a.video_speed);
    s.camera = visionOnlyCamera(video->width(), video->height(), video->frameRateHz(), p.calibration,
                                &s.calibration_from);
    s.source = std::move(video);
  } else {
    data::V4l2Request request = a.v4l2_request;
    if (!a.v4l2_size.empty() && std::sscanf(a.v4l2_size.c_str(), "%dx%d", &request.width, &request.height) != 2)
      throw data::InputError("--v4l2-size", 0, "v4l2_size", "must be WxH, e.g. 640x480");
    auto camera = std::make_unique<data::V4l2CameraSource>(a.v4l2, request);
    s.camera = visionOnlyCamera(camera->width(), camera->height(), camera->frameRateHz(), p.calibration,
                                &s.calibration_from);
    s.source = std::move(camera);
  }
  return withStartAndDuration(std::move(s), a.sequence);
}

}  // namespace adugs::app
