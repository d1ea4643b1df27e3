#include "app/run_config.h"

#include <algorithm>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "data/builtin_config.h"
#include "data/yaml_options.h"

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
    tracking::DynamicMaskerOptions& o = c.dynamic;
    d.optional("detect_every", o.detect_every, 1, 1000);
    std::string tracker = "sort", noise = "adaptive";
    d.optional("tracker", tracker);
    if (tracker != "sort" && tracker != "none") d.fail("tracker", "must be sort or none");
    o.track = tracker == "sort";
    d.optional("noise", noise);
    if (noise != "adaptive" && noise != "fixed") d.fail("noise", "must be adaptive or fixed");
    d.optional("max_age", o.sort.max_age, 0, 1000);
    d.optional("min_hits", o.sort.min_hits, 0, 1000);
    d.optional("iou_min", o.sort.iou_min, 0.0, 1.0);
    d.optional("lambda", o.sort.filter.lambda, 1e-6, 1e6);
    d.optional("beta_pos", o.sort.filter.beta_pos, 1e-6, 1e6);
    d.optional("beta_size", o.sort.filter.beta_size, 1e-6, 1e6);
    d.optional("window", o.sort.filter.window, 1, 1000);
    if (noise == "fixed") o.sort.filter.lambda = 1e6;  // erf saturates at once: R = beta, a fixed R
    d.optional("erode_radius_px", o.refinement.erode_radius_px, 0, 100);
    d.optional("dilate_radius_px", o.refinement.dilate_radius_px, 0, 200);
    d.optional("min_box_side_px", o.min_box_side_px, 0.0, 1000.0);
    d.optional("segment_every", o.segment_every, 0, 1000);
    d.optional("segment_async", o.segment_async);
    d.optional("camera_motion_compensation", o.camera_motion_compensation);
    d.optional("appearance_weight", o.sort.appearance_weight, 0.0, 10.0);
    d.optional("high_score", o.sort.high_score, 0.0, 1.0);
    d.optional("drop_unconfirmed", o.sort.drop_unconfirmed_on_miss);
    d.optional("last_box_association", o.sort.last_box_association);
    d.optional("direction_weight", o.sort.direction_weight, 0.0, 10.0);
    if (!o.track && o.detect_every != 1) d.fail("detect_every", "detecting every n-th frame needs tracker: sort");
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
    data::PlaybackOptions& o = c.playback;
    p.optional("image_topic", o.topics.image);
    p.optional("imu_topic", o.topics.imu);
    p.optional("accel_topic", o.topics.accel);
    p.optional("gyro_topic", o.topics.gyro);
    p.optional("gt_topic", o.gt_topic);
    p.optional("gt_parent_frame", o.gt_parent_frame);
    p.optional("gt_child_frame", o.gt_child_frame);
    double window_s = data::nsToSec(o.reorder_window_ns);
    p.optional("reorder_window_s", window_s, 0.0, 10.0);
    o.reorder_window_ns = data::secToNs(window_s);
    p.finish();
  }
  if (r.has("d435i")) {
    data::YamlOptionsReader d = r.child("d435i");
    readD435iOptions(d, &c.d435i);
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

RunConfigChoice chooseRunConfig(const data::CameraCalibration& camera, bool simulated) {
  std::ostringstream what;
  what << std::setprecision(3) << camera.rate_hz << " Hz camera";  // a bag's measured rate: 30.5, not 30.5095
  const bool ideal_pinhole =
      camera.distortion_model == data::DistortionModel::kRadialTangential &&
      std::all_of(camera.distortion.begin(), camera.distortion.end(), [](double k) { return k == 0.0; });
  if (simulated) return {"sim.yaml", "written by adugs sim with a simulated IMU: the simulator class"};
  if (camera.rate_hz >= 25.0) return {"d435i.yaml", what.str() + ": the RealSense D435i class (30 Hz)"};
  if (!(camera.rate_hz > 0))
    return {"euroc.yaml", "camera rate unknown: the EuRoC class (global shutter, 20 Hz)"};
  if (ideal_pinhole)
    return {"sim.yaml", what.str() + " without lens distortion: the simulator class (rendered images, e.g. VIODE)"};
  return {"euroc.yaml", what.str() + " with lens distortion: the EuRoC class (global shutter, 20 Hz)"};
}

RunConfig runConfigFor(const std::string& path, const data::OpenedSequence& sequence, std::string* described) {
  if (!path.empty()) {
    *described = path;
    return loadRunConfig(path);
  }
  const RunConfigChoice choice = chooseRunConfig(sequence.camera, sequence.simulated);
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
