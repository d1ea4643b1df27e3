#include "data/sim/sim_sequence.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "data/formats/calibration_files.h"
#include "data/formats/imu_csv.h"
#include "data/formats/trajectory_io.h"
#include "data/input_error.h"
#include "data/sim/sim_hybrid.h"
#include "data/sim/sim_renderer.h"
#include "data/sim/sim_sequence_writer.h"

namespace adugs::data {

namespace fs = std::filesystem;

namespace {

// What the frame loop needs, whichever mode produced it.
struct Prepared {
  std::unique_ptr<SimTrajectory> trajectory;
  SimCamera camera;
  Eigen::Isometry3d T_B_C;
  double camera_rate_hz = 20;
  ImuNoise imu_noise;
  std::vector<ImuSample> imu;
  std::vector<GroundTruthState> ground_truth;
};

ImuNoise noiseOf(const SimImuOptions& o) {
  ImuNoise n;
  n.gyro_noise_density = o.gyro_noise_density;
  n.gyro_random_walk = o.gyro_random_walk;
  n.accel_noise_density = o.accel_noise_density;
  n.accel_random_walk = o.accel_random_walk;
  n.rate_hz = o.rate_hz;
  return n;
}

Prepared prepareSynthetic(const SimSequenceOptions& o) {
  Prepared p;
  const int64_t end = o.start_ns + secToNs(o.duration_s);
  p.trajectory = std::make_unique<SineTrajectory>(makeSceneTrajectory(o.scene, o.seed, o.start_ns, end, o.motion));
  p.camera = o.camera;
  if (!o.camera_path.empty()) {
    // Any calibration file the product reads (EuRoC, Kalibr, OpenVINS, VINS, Basalt): its cam0's lens.
    const RigCalibration rig = readCalibrationFiles({o.camera_path});
    if (rig.cameras.empty()) throw InputError(o.camera_path, 0, "cameras", "the file has no camera");
    p.camera = simCameraFromCalibration(rig.cameras[0].camera, rig.cameras[0].source);
  }
  p.T_B_C = o.T_B_C;
  p.camera_rate_hz = o.camera_rate_hz;
  SimImuOptions imu = o.imu;
  imu.seed = o.seed;
  if (!o.imu_calib_path.empty()) {
    // Simulate a given IMU (e.g. a D435i's Kalibr imu.yaml converted to EuRoC form).
    const ImuNoise given = readEurocImuYaml(o.imu_calib_path);
    imu.gyro_noise_density = given.gyro_noise_density;
    imu.gyro_random_walk = given.gyro_random_walk;
    imu.accel_noise_density = given.accel_noise_density;
    imu.accel_random_walk = given.accel_random_walk;
  }
  p.imu_noise = noiseOf(imu);
  for (const SimImuRecord& r : synthesizeImu(*p.trajectory, imu)) {
    p.imu.push_back(r.sample);
    GroundTruthState g;
    g.pose.t_ns = r.truth.t_ns;
    g.pose.p_W_B = r.truth.p_W_B;
    g.pose.q_W_B = r.truth.q_W_B;
    g.has_velocity_and_biases = true;
    g.v_W = r.truth.v_W;
    g.gyro_bias = r.gyro_bias;
    g.accel_bias = r.accel_bias;
    p.ground_truth.push_back(g);
  }
  return p;
}

Prepared prepareHybrid(const SimSequenceOptions& o) {
  Prepared p;
  std::vector<GroundTruthState> states = readGroundTruthStates(o.trajectory_path);
  if (o.duration_s > 0) {
    const int64_t end = states.front().pose.t_ns + secToNs(o.duration_s);
    while (states.size() > 2 && states.back().pose.t_ns > end) states.pop_back();
  }
  if (states.size() < 2)
    throw InputError(o.trajectory_path, 0, "", "need at least two poses to follow");
  p.ground_truth = states;
  p.trajectory = std::make_unique<InterpolatedTrajectory>(states);

  const CameraCalibration calib = readEurocCameraYaml(o.calib_path);
  p.camera = simCameraFromCalibration(calib, o.calib_path);
  p.T_B_C = calib.T_B_C;
  p.camera_rate_hz = calib.rate_hz > 0 ? calib.rate_hz : o.camera_rate_hz;

  const std::vector<ImuSample> imu = readEurocImuCsv(o.imu_path);
  checkImuCoverage(imu, o.imu_path, p.trajectory->startNs(), p.trajectory->endNs());
  for (const ImuSample& s : imu)
    if (s.t_ns >= p.trajectory->startNs() && s.t_ns <= p.trajectory->endNs()) p.imu.push_back(s);

  std::string imu_yaml = o.imu_calib_path;
  if (imu_yaml.empty()) {
    const fs::path sibling = fs::path(o.imu_path).parent_path() / "sensor.yaml";
    if (fs::exists(sibling)) imu_yaml = sibling.string();
  }
  p.imu_noise = imu_yaml.empty() ? noiseOf(o.imu) : readEurocImuYaml(imu_yaml);
  return p;
}

std::string matrixYaml(const Eigen::Matrix4d& m) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (int i = 0; i < 16; ++i) s << (i ? ", " : "") << m(i / 4, i % 4);
  s << "]";
  return s.str();
}

std::string infoYaml(const SimSequenceOptions& o, const Prepared& p, const SimScene& scene, int frames) {
  std::ostringstream s;
  s.precision(17);
  s << "# adugs sim: how this sequence was generated\n";
  s << "mode: " << (isHybrid(o) ? "hybrid" : "synthetic") << "\n";
  s << "scene: " << o.scene << "\nlevel: " << toString(o.level) << "\nseed: " << o.seed << "\n";
  if (!isHybrid(o)) s << "motion: " << o.motion << "\n";
  if (!isHybrid(o) && !o.camera_path.empty()) s << "camera: " << o.camera_path << "\n";
  if (isHybrid(o))
    s << "trajectory: " << o.trajectory_path << "\nimu: " << o.imu_path << "\ncalib: " << o.calib_path << "\n";
  s << "start_ns: " << p.trajectory->startNs() << "\nend_ns: " << p.trajectory->endNs() << "\n";
  s << "camera_rate_hz: " << p.camera_rate_hz << "\nframes: " << frames << "\n";
  s << "timeshift_cam_imu: " << o.time_offset_s << "  # t_imu = t_cam + timeshift\n";
  s << "T_B_C: " << matrixYaml(p.T_B_C.matrix()) << "\n";
  s << "imu_noise: " << (isHybrid(o) ? "real" : (o.imu.noise ? "on" : "off")) << "\n";
  if (!isHybrid(o)) {
    const Eigen::Vector3d& b = o.imu.initial_accel_bias;
    std::ostringstream v;  // as given, not at the stream's full precision
    v << "[" << b.x() << ", " << b.y() << ", " << b.z() << "]";
    s << "initial_accel_bias: " << v.str() << "  # m/s^2\n";
  }
  s << "pixel_noise_sigma: " << o.pixel_noise_sigma << "\nexposure_variation: " << o.exposure_variation
    << "\nblur_samples: " << o.blur_samples << "\nexposure_ms: " << o.exposure_ms << "\nvignetting: " << o.vignetting
    << "\n";
  s << "objects:\n";
  for (const SimObject& obj : scene.objects)
    s << "  - {id: " << obj.id << ", class: " << toString(obj.cls) << ", coco_class: "
      << cocoClassId(obj.cls) << ", size: [" << obj.size.x() << ", " << obj.size.y() << ", "
      << obj.size.z() << "]" << (obj.moves() ? "" : ", moving: false") << "}\n";
  return s.str();
}

void checkOptions(const SimSequenceOptions& o) {
  checkSimSceneName(o.scene);
  checkSimMotionName(o.motion);
  if (!isHybrid(o) && !(o.duration_s > 0))
    throw InputError("command line", 0, "--duration", "must be positive (seconds)");
  if (!(o.camera_rate_hz > 0)) throw InputError("command line", 0, "--rate", "must be positive (Hz)");
  if (!(o.imu.rate_hz > 0)) throw InputError("command line", 0, "--imu-rate", "must be positive (Hz)");
  if (o.blur_samples < 1) throw InputError("command line", 0, "--blur-samples", "must be at least 1");
  if (!(o.vignetting >= 0 && o.vignetting < 1))
    throw InputError("command line", 0, "--vignetting", "must be in [0, 1) (the light lost in the farthest corner)");
  const int given = !o.trajectory_path.empty() + !o.imu_path.empty() + !o.calib_path.empty();
  if (given != 0 && given != 3)
    throw InputError("command line", 0, "--trajectory/--imu/--calib", "hybrid mode needs all three files");
  if (o.standing < 0 || o.standing > 100)
    throw InputError("command line", 0, "--standing", "must be in [0, 100] (people standing still, and as many parked cars in the street)");
  if (o.people != "boxes" && o.people != "walkers")
    throw InputError("command line", 0, "--people", "unknown '" + o.people + "' (use boxes or walkers)");
  if (isHybrid(o) && o.motion != "glide")
    throw InputError("command line", 0, "--motion", "hybrid mode follows the given trajectory; leave --motion out");
}

}  // namespace

bool isHybrid(const SimSequenceOptions& o) {
  return !o.trajectory_path.empty() && !o.imu_path.empty() && !o.calib_path.empty();
}

void generateSimSequence(const SimSequenceOptions& o, const std::string& out_root) {
  checkOptions(o);
  const Prepared p = isHybrid(o) ? prepareHybrid(o) : prepareSynthetic(o);
  SimScene scene = buildStaticScene(o.scene, o.seed, *p.trajectory);
  SimWalkerSet walkers;
  if (o.people == "walkers") {
    const std::string dir = o.walkers_dir.empty() ? defaultWalkersDir() : o.walkers_dir;
    if (dir.empty())
      throw InputError("command line", 0, "--people",
                       "walkers need the sprites cut from vtest.avi at build time: install Debian's opencv-doc and "
                       "rebuild, or give --walkers DIR");
    walkers = loadWalkerSet(dir);
  }
  addDynamicObjects(scene, o.level, o.seed, *p.trajectory, p.T_B_C, o.people == "walkers" ? &walkers : nullptr);
  addStandingObjects(scene, o.standing, o.seed, *p.trajectory, o.people == "walkers" ? &walkers : nullptr);

  SimSequenceWriter writer(out_root, calibrationFromSimCamera(p.camera, p.T_B_C, p.camera_rate_hz),
                           p.imu_noise);
  writer.writeImu(p.imu);
  writer.writeGroundTruth(p.ground_truth);

  SimRenderer renderer(p.camera);
  const int64_t offset_ns = secToNs(o.time_offset_s);
  const int64_t period_ns = secToNs(1.0 / p.camera_rate_hz);
  const int64_t start = p.trajectory->startNs(), end = p.trajectory->endNs();
  // Image stamps on the camera clock; the exposure happens at IMU time stamp + offset.
  const int64_t first = start - offset_ns;
  const int64_t total = (end - offset_ns - first) / period_ns + 1;
  auto poseAt = [&](int64_t t_imu) {
    const SimBodyState s = p.trajectory->stateAt(t_imu);
    Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
    T_W_B.linear() = s.q_W_B.toRotationMatrix();
    T_W_B.translation() = s.p_W_B;
    return Eigen::Isometry3d(T_W_B * p.T_B_C);
  };

  SimRenderOptions ropt;
  ropt.noise_sigma = o.pixel_noise_sigma;
  ropt.vignetting = o.vignetting;
  ropt.noise_seed = o.seed;
  ropt.blur_samples = o.blur_samples;
  ropt.exposure_ns = secToNs(o.exposure_ms * 1e-3);
  const std::string label = o.scene + "/" + toString(o.level);
  SimFrame frame;
  int64_t k = 0;
  for (int64_t t_cam = first; t_cam + offset_ns <= end; t_cam += period_ns, ++k) {
    const int64_t t_imu = t_cam + offset_ns;
    const double ts = nsToSec(t_imu - start);
    ropt.exposure_gain = static_cast<float>(
        1.0 + o.exposure_variation * (0.7 * std::sin(2 * M_PI * ts / 6.3) + 0.3 * std::sin(2 * M_PI * ts / 1.9)));
    renderer.render(scene, poseAt, t_imu, ropt, &frame);
    writer.writeFrame(t_cam, frame);
    if (o.progress && (k % 100 == 99 || k + 1 == total))
      std::cerr << "adugs sim: " << label << ": frame " << (k + 1) << "/" << total << "\n";
  }
  writer.writeInfo(infoYaml(o, p, scene, writer.framesWritten()));
}

}  // namespace adugs::data
