#include "app/run_config.h"

#include <algorithm>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "data/builtin_config.h"
#include "data/formats/yaml_options.h"

namespace adugs::app {

namespace {

RunConfig readRunConfig(data::YamlOptionsReader& r) {
  RunConfig c;
  if (r.has("tracker")) {
    data::YamlOptionsReader t = r.child("tracker");
    vio::readFeatureTrackerOptions(t, &c.tracker);
    t.finish();
  }
  if (r.has("estimator")) {
    data::YamlOptionsReader e = r.child("estimator");
    vio::readEstimatorOptions(e, &c.estimator);
    e.finish();
  }
  if (r.has("dynamic")) {
    data::YamlOptionsReader d = r.child("dynamic");
    tracking::readDynamicMaskerOptions(d, &c.dynamic);
    d.finish();
  }
  if (r.has("pipeline")) {
    data::YamlOptionsReader p = r.child("pipeline");
    p.optional("frame_queue", c.pipeline.frame_queue, 1, 1000);
    p.optional("test_estimator_delay_ms", c.pipeline.test_estimator_delay_ms, 0.0, 60000.0);
    p.finish();
  }
  if (r.has("playback")) {
    data::YamlOptionsReader p = r.child("playback");
    data::readPlaybackConfig(p, &c.playback);
    p.finish();
  }
  if (r.has("d435i")) {
    data::YamlOptionsReader d = r.child("d435i");
    data::readD435iOptions(d, &c.d435i);
    d.finish();
  }
  r.finish();
  return c;
}

}  // namespace

RunConfig loadRunConfig(const std::string& path) {
  if (path.empty()) return RunConfig{};
  data::YamlOptionsReader r = data::YamlOptionsReader::fromFile(path);
  return readRunConfig(r);
}

RunConfigChoice chooseRunConfig(const data::CameraCalibration& camera, data::SimFolder folder) {
  std::ostringstream what;
  what << std::setprecision(3) << camera.rate_hz << " Hz camera";  // a bag's measured rate: 30.5, not 30.5095
  // No distortion: 'none', or radtan with zero coefficients (equidistant always bends rays).
  const bool ideal_pinhole =
      camera.projection == data::ProjectionModel::kPinhole &&
      (camera.distortion_model == data::DistortionModel::kNone ||
       (camera.distortion_model == data::DistortionModel::kRadialTangential &&
        std::all_of(camera.distortion.begin(), camera.distortion.end(), [](double k) { return k == 0.0; })));
  if (folder == data::SimFolder::kSynthetic)
    return {"sim.yaml", "written by adugs sim with a simulated IMU: the simulator class"};
  if (camera.rate_hz >= 25.0) return {"d435i.yaml", what.str() + ": the RealSense D435i class (30 Hz)"};
  if (!(camera.rate_hz > 0))
    return {"euroc.yaml", "camera rate unknown: the EuRoC class (global shutter, 20 Hz)"};
  // Rendered without distortion along a real flight, the IMU is a real one (EuRoC's ADIS16448): the
  // EuRoC class's IMU settings fit it (doc/results.md, "The real IMU's noise").
  if (ideal_pinhole && folder == data::SimFolder::kHybrid)
    return {"euroc.yaml", what.str() + " rendered along a real flight (real IMU): the EuRoC class"};
  if (ideal_pinhole)
    return {"sim.yaml", what.str() + " without lens distortion: the simulator class (rendered images, e.g. VIODE)"};
  return {"euroc.yaml", what.str() + " with lens distortion: the EuRoC class (global shutter, 20 Hz)"};
}

RunConfig runConfigFor(const std::string& path, const data::OpenedSequence& sequence, std::string* described) {
  if (!path.empty()) {
    *described = path;
    return loadRunConfig(path);
  }
  const RunConfigChoice choice = chooseRunConfig(sequence.camera, sequence.sim_folder);
  const std::string text = data::builtinConfigText(choice.name);
  if (text.empty()) throw std::logic_error("data/config/" + choice.name + " is not built into this adugs");
  *described = "data/config/" + choice.name + " (built in; " + choice.reason + ")";
  data::YamlOptionsReader r = data::YamlOptionsReader::fromString(text, "built-in data/config/" + choice.name);
  return readRunConfig(r);
}

void applyPlaybackConfig(const data::PlaybackOptions& config, bool window_given, data::PlaybackOptions* o) {
  auto fill = [](std::string& field, const std::string& value) {
    if (field.empty()) field = value;
  };
  // One IMU topic or two: the command line's choice of layout wins as a whole.
  const bool cli_imu = !o->topics.imu.empty() || !o->topics.accel.empty() || !o->topics.gyro.empty();
  fill(o->topics.image, config.topics.image);
  if (!cli_imu) {
    o->topics.imu = config.topics.imu;
    o->topics.accel = config.topics.accel;
    o->topics.gyro = config.topics.gyro;
  }
  fill(o->gt_topic, config.gt_topic);
  fill(o->gt_parent_frame, config.gt_parent_frame);
  fill(o->gt_child_frame, config.gt_child_frame);
  if (!window_given) o->reorder_window_ns = config.reorder_window_ns;
}

}  // namespace adugs::app
