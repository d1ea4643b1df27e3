// Measures what the intrinsics verdict checks see on sets of known quality, to choose (and
// re-check) the verdict's default bounds: synthetic views with known intrinsics (well spread,
// few views, near-still), and the real EuRoC cam0 detections against the published intrinsics
// (cam_april; imu_april as random subsets, as consecutive 1.5 s windows like cam_april, and
// subsampled). One TSV row per calibration on stdout. Not a Google Benchmark: a measurement
// program (doc/calibration.md, "Verdicts", says how its output chose the bounds).
//
//   build/tests/bench/bench_calib_verdicts [--quick] > verdicts.tsv
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "calib/camera_imu/camera_imu_input.h"
#include "calib/camera_imu/camera_imu_report.h"
#include "calib/camera_imu/camera_imu_verdict.h"
#include "calib/imu_noise/allan_variance.h"
#include "calib/imu_noise/imu_noise_verdict.h"
#include "calib/intrinsics/intrinsics_calibrator.h"
#include "calib/intrinsics/intrinsics_verdict.h"
#include "calib/target/corner_csv.h"
#include "calib/text_format.h"
#include "data/input_error.h"
#include "tests/calib/camera_imu_synthetic.h"
#include "tests/calib/imu_noise_synthetic.h"
#include "tests/calib/synthetic_views.h"
#include "tests/test_support.h"

namespace {
using namespace adugs::calib;

void header() {
  std::printf(
      "set\tviews\tverdict\tfu_err_pct\tfv_err_pct\tpu_err_pct\tpv_err_pct\tmax_f_err_pct\t"
      "max_pp_err_pct\trms_px\timage_share\ttilt_spread_deg\tmax_tilt_deg\tfu_rel_sigma_pct\t"
      "pu_rel_sigma_pct\tmax_dist_sigma_px\tmax_f_shift_pct\tmax_pp_shift_pct\toutliers\t"
      "start_px\tfindings\n");
}

void run(const std::string& name, const std::vector<TargetObservation>& views,
         const CalibCamera& truth) {
  IntrinsicsOptions o;
  o.model = truth.model;
  IntrinsicsResult r;
  try {
    r = calibrateIntrinsics(views, truth.width, truth.height, o);
  } catch (const std::exception& e) {
    std::printf("%s\t%zu\terror\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t%s\n", name.c_str(), views.size(), e.what());
    return;
  }
  const IntrinsicsJudgement j = judgeIntrinsics(r, o);
  const CalibCamera& c = r.camera;
  double err[4];
  for (int i = 0; i < 4; ++i) err[i] = 100 * (c.params[i] - truth.params[i]) / truth.params[i];
  const double max_dist_sigma = j.distortion_sigma_px;
  const double f_shift = 100 * std::max(std::abs(j.rejection_shift[0] / c.params[0]),
                                        std::abs(j.rejection_shift[1] / c.params[1]));
  const double pp_shift = 100 * std::max(std::abs(j.rejection_shift[2]), std::abs(j.rejection_shift[3])) / c.width;
  std::string findings;
  for (const auto& f : j.verdict.findings) findings += (findings.empty() ? "" : ",") + f.check;
  std::printf("%s\t%zu\t%s\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%.2f\t%.2f\t%.4f\t%.4f\t%.3f\t%.3f\t%.3f\t%d\t%.1f\t%s\n",
              name.c_str(), r.views.size(), verdictName(j.verdict.verdict), err[0], err[1], err[2],
              err[3], std::max(std::abs(err[0]), std::abs(err[1])),
              std::max(std::abs(err[2]), std::abs(err[3])), r.rms_px, j.coverage.image_share,
              j.coverage.tilt_spread_deg, j.coverage.max_tilt_deg,
              r.has_sigma ? 100 * r.sigma[0] / c.params[0] : -1,
              r.has_sigma ? 100 * std::max(r.sigma[2], r.sigma[3]) / c.width : -1, max_dist_sigma,
              f_shift, pp_shift, r.outliers, r.initial_focal_px, findings.c_str());
  std::fflush(stdout);
}

std::vector<TargetObservation> pick(const std::vector<TargetObservation>& all,
                                    const std::vector<size_t>& idx) {
  std::vector<TargetObservation> out;
  for (size_t i : idx) out.push_back(all[i]);
  return out;
}

void runCameraImu(const std::string& name, const std::vector<TargetObservation>& views,
                  const CalibCamera& camera, const ImuRecording& imu, const ImuNoiseFigures& noise,
                  double gravity, const Eigen::Isometry3d& T_C_I_truth, double shift_truth) {
  CameraImuOptions o;
  o.gravity = gravity;
  CameraImuResult r;
  try {
    r = calibrateCameraImu(views, camera, imu, noise, o);
  } catch (const std::exception& e) {
    std::printf("%s\terror\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t%s\n", name.c_str(), e.what());
    return;
  }
  const CalibrationVerdict v = judgeCameraImu(r, o);
  double angle = 0, dist = 0;
  compareTransforms(r.T_C_I, T_C_I_truth, angle, dist);
  const double dp = (r.T_C_I.inverse().translation() - T_C_I_truth.inverse().translation()).norm();
  std::string findings;
  for (const auto& f : v.findings) findings += (findings.empty() ? "" : ",") + f.check;
  std::printf("%s\t%s\t%.1f\t%d\t%.3f\t%.1f\t%.3f\t%.3f\t%.3f\t%.3f\t%.2f\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%.1f\t%s\n",
              name.c_str(), verdictName(v.verdict), r.duration_s, r.frames_used, angle, dp * 1000,
              (r.time_shift_s - shift_truth) * 1000, r.excitation(0), r.excitation(2),
              r.has_sigma ? r.sigma_rotation.maxCoeff() * 180 / M_PI : -1,
              r.has_sigma ? r.sigma_translation.maxCoeff() * 1000 : -1,
              r.has_sigma ? r.sigma_time_shift_s * 1000 : -1, r.reprojection_rms_px,
              r.accel_bias.norm(), r.gyro_bias.norm(), r.T_C_I.inverse().translation().norm(),
              r.seconds, findings.c_str());
  std::fflush(stdout);
}

int cameraImuSets(bool quick) {
  std::printf("set\tverdict\tduration_s\tframes\trot_err_deg\ttrans_err_mm\tshift_err_ms\t"
              "excitation_max\texcitation_min\trot_sigma_deg\ttrans_sigma_mm\tshift_sigma_ms\t"
              "rms_px\taccel_bias\tgyro_bias\tdistance_m\tseconds\tfindings\n");
  // Synthetic (tests/calib/camera_imu_synthetic.h): known T_C_I and a 5 ms shift.
  for (double duration : {4.0, 8.0, 16.0})
    for (unsigned seed = 1; seed <= (quick ? 1u : 3u); ++seed) {
      const auto rec = synth::makeCameraImuRecording(duration, 0.005, 0.3, seed);
      runCameraImu("synthetic_full_" + std::to_string(static_cast<int>(duration)) + "s_s" + std::to_string(seed),
                   rec.views, rec.camera, rec.imu, rec.noise, adugs::data::kSimGravity, rec.T_C_I, 0.005);
    }
  for (auto [motion, label] : {std::pair{synth::RigMotion::kPlanar, "planar"}, std::pair{synth::RigMotion::kStill, "still"}})
    for (unsigned seed = 1; seed <= (quick ? 1u : 2u); ++seed) {
      const auto rec = synth::makeCameraImuRecording(16.0, 0.005, 0.3, seed, 1'000'000'000'000, true, motion);
      runCameraImu(std::string("synthetic_") + label + "_16s_s" + std::to_string(seed), rec.views, rec.camera,
                   rec.imu, rec.noise, adugs::data::kSimGravity, rec.T_C_I, 0.005);
    }
  {  // the IMU stops half-way through the images
    auto rec = synth::makeCameraImuRecording(16.0, 0.005, 0.3, 1);
    const size_t half = rec.imu.t_ns.size() / 2;
    rec.imu.t_ns.resize(half), rec.imu.gyro.resize(half), rec.imu.accel.resize(half);
    runCameraImu("synthetic_imu_half_16s", rec.views, rec.camera, rec.imu, rec.noise,
                 adugs::data::kSimGravity, rec.T_C_I, 0.005);
  }
  // EuRoC imu_april windows against the published T_BS.
  const auto shared = adugs::test::sharedDataDir();
  const auto dir = shared / "euroc_calib_aprilgrid" / "imu_april";
  const auto reference = shared / "euroc_v101_micro" / "mav0" / "cam0" / "sensor.yaml";
  if (!std::filesystem::exists(dir) || !std::filesystem::exists(reference)) {
    std::fprintf(stderr, "shared data not found at %s: real sets skipped\n", dir.c_str());
    return 0;
  }
  const CameraImuSensors sensors = readYacCalibConfig((dir / "config.yaml").string());
  const auto views = readCornerCsvs((dir / "cam0").string(), nullptr);
  const ImuRecording imu = readImuCsv((dir / "imu0.csv").string());
  const Eigen::Isometry3d T_C_I_ref = readEurocCameraToImu(reference.string()).inverse();
  std::vector<std::pair<double, double>> windows;  // start, duration [s]
  for (double d : {3.0, 5.0, 7.0, 10.0})
    for (double at : quick ? std::vector<double>{0, 36} : std::vector<double>{0, 18, 36, 54}) windows.push_back({at, d});
  for (double at : quick ? std::vector<double>{0} : std::vector<double>{0, 26, 52}) windows.push_back({at, 20});
  if (!quick) windows.push_back({0, 36}), windows.push_back({36, 36});
  windows.push_back({0, 80});
  for (auto [at, d] : windows) {
    std::vector<TargetObservation> part;
    for (const auto& v : views) {
      const double t = static_cast<double>(v.t_ns - views.front().t_ns) * 1e-9;
      if (t >= at && t < at + d) part.push_back(v);
    }
    runCameraImu(strprintf("euroc_imu_april_%gs_at%gs", d, at), part, sensors.camera, imu, sensors.imu,
                 sensors.gravity, T_C_I_ref, 0);
  }
  return 0;
}

double adevAt(const SensorNoise& n, double tau) {  // mean over axes, nearest cluster time
  size_t best = 0;
  for (size_t i = 0; i < n.curve.tau.size(); ++i)
    if (std::abs(std::log(n.curve.tau[i] / tau)) < std::abs(std::log(n.curve.tau[best] / tau))) best = i;
  return n.curve.adev.empty() ? 0 : n.curve.adev[best].mean();
}

// The Allan analysis against simulated static recordings of several lengths (the errors of N and
// K), and what a moving recording looks like (EuRoC imu_april, the V1_01 flight).
int allanSets(bool quick) {
  std::printf("set\tduration_s\tverdict\tgyro_N_err_pct\tgyro_K_err_pct\taccel_N_err_pct\t"
              "accel_K_err_pct\tgyro_rw_ratio\taccel_rw_ratio\tgyro_adev1s\taccel_adev1s\tfindings\n");
  const double rate = 200, gN = 1.7e-4, gK = 1.9e-5, aN = 2e-3, aK = 3e-3;  // EuRoC's figures
  auto row = [&](const std::string& name, const ImuRecording& rec, double gn, double gk, double an, double ak) {
    const ImuNoiseResult r = estimateImuNoise(rec);
    const CalibrationVerdict v = judgeImuNoise(r);
    std::string findings;
    for (const auto& f : v.findings) findings += (findings.empty() ? "" : ",") + f.check;
    auto pct = [](double got, double truth) { return truth > 0 ? 100 * (got - truth) / truth : 0.0; };
    std::printf("%s\t%.0f\t%s\t%.1f\t%.1f\t%.1f\t%.1f\t%.2f\t%.2f\t%.3g\t%.3g\t%s\n", name.c_str(),
                r.duration_s, verdictName(v.verdict), pct(r.gyro.white, gn), pct(r.gyro.random_walk, gk),
                pct(r.accel.white, an), pct(r.accel.random_walk, ak), randomWalkVisibility(r.gyro, r.duration_s),
                randomWalkVisibility(r.accel, r.duration_s), adevAt(r.gyro, 1), adevAt(r.accel, 1), findings.c_str());
    std::fflush(stdout);
  };
  for (double minutes : {1.0, 5.0, 15.0, 30.0, 60.0, 120.0}) {
    for (unsigned seed = 1; seed <= (quick ? 2u : 6u); ++seed) {
      std::mt19937_64 rng(seed);
      const size_t n = static_cast<size_t>(minutes * 60 * rate);
      ImuRecording rec;
      rec.rate_hz = rate;
      rec.gyro = synth::staticImuAxes(gN, gK, rate, n, rng);
      rec.accel = synth::staticImuAxes(aN, aK, rate, n, rng);
      for (size_t i = 0; i < n; ++i) rec.t_ns.push_back(static_cast<int64_t>(i) * 5000000);
      row(strprintf("simulated_static_%gmin_s%u", minutes, seed), rec, gN, gK, aN, aK);
    }
  }
  const auto shared = adugs::test::sharedDataDir();
  for (const auto& path : {shared / "euroc_calib_aprilgrid" / "imu_april" / "imu0.csv",
                           shared / "euroc_v101_micro" / "mav0" / "imu0" / "data.csv"}) {
    if (!std::filesystem::exists(path)) continue;
    row("moving_" + path.parent_path().filename().string(), readImuCsv(path.string()), 0, 0, 0, 0);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, camera_imu = false, allan = false;
  for (int i = 1; i < argc; ++i) {
    quick |= std::strcmp(argv[i], "--quick") == 0;
    camera_imu |= std::strcmp(argv[i], "--camera-imu") == 0;
    allan |= std::strcmp(argv[i], "--allan") == 0;
  }
  if (camera_imu) return cameraImuSets(quick);
  if (allan) return allanSets(quick);
  const int seeds = quick ? 2 : 5;
  header();
  const AprilGrid grid = synth::eurocGrid();
  const CalibCamera euroc = synth::eurocLikeCamera();
  CalibCamera cam1 = euroc;  // EuRoC's cam1 (the camera of issue 18's weak case)
  cam1.params = {457.587, 456.134, 379.999, 255.238, -0.28368365, 0.07451284, -0.00010473, -3.555e-05};

  // Synthetic: well-spread views of several sizes and noise levels.
  for (int n : {5, 10, 25})
    for (double noise : {0.2, 0.5})
      for (int s = 1; s <= seeds; ++s)
        run("synthetic_spread_n" + std::to_string(n) + "_noise" + std::to_string(noise).substr(0, 3) +
                "_s" + std::to_string(s),
            synth::syntheticViews(euroc, grid, n, noise, static_cast<unsigned>(s)), euroc);
  for (int s = 1; s <= seeds; ++s)
    run("synthetic_fisheye_n25_s" + std::to_string(s),
        synth::syntheticViews(synth::fisheyeCamera(), grid, 25, 0.2, static_cast<unsigned>(10 + s), 0.35, 0.7),
        synth::fisheyeCamera());
  // Synthetic near-still: one pose held (face-on centred; face-on at the side; tilted 10 deg).
  struct Still { const char* name; double dist, tilt, jm, jd, ox, oy, noise; };
  for (const Still& p : {Still{"single_pose_tilt20", 1.0, 20, 0, 0, 0, 0, 0.3},
                         Still{"still_faceon", 1.1, 0, 0.002, 0.1, 0, 0, 0.2},
                         Still{"still_side", 1.15, 1, 0.002, 0.1, -0.3, -0.15, 0.3},
                         Still{"still_tilt10", 1.15, 10, 0.02, 1.0, -0.1, 0.0, 0.3},
                         Still{"still_tilt25", 1.0, 25, 0.02, 1.0, 0.0, 0.0, 0.3}})
    for (int s = 1; s <= seeds; ++s)
      run(std::string("synthetic_") + p.name + "_s" + std::to_string(s),
          synth::nearStillViews(cam1, grid, 30, p.noise, static_cast<unsigned>(s), p.dist, p.tilt,
                                p.jm, p.jd, p.ox, p.oy),
          cam1);

  // Real EuRoC cam0 detections against the published cam0 intrinsics.
  const auto shared = adugs::test::sharedDataDir() / "euroc_calib_aprilgrid";
  if (!std::filesystem::exists(shared)) {
    std::fprintf(stderr, "shared data not found at %s: real sets skipped\n", shared.c_str());
    return 0;
  }
  const auto cam_april = readCornerCsvs((shared / "cam_april" / "cam0").string(), nullptr);
  run("euroc_cam_april_all30", cam_april, euroc);
  const auto imu_april = readCornerCsvs((shared / "imu_april" / "cam0").string(), nullptr);
  std::vector<size_t> with;  // frames with enough corners
  for (size_t i = 0; i < imu_april.size(); ++i)
    if (imu_april[i].corners.size() >= 12) with.push_back(i);
  for (int every : {10, 20}) {
    std::vector<size_t> idx;
    for (size_t i = 0; i < imu_april.size(); i += every) idx.push_back(i);
    run("euroc_imu_april_every" + std::to_string(every), pick(imu_april, idx), euroc);
  }
  std::mt19937 rng(1);
  for (int n : {10, 20, 30, 60})
    for (int s = 1; s <= seeds; ++s) {
      std::vector<size_t> idx = with;
      std::shuffle(idx.begin(), idx.end(), rng);
      idx.resize(static_cast<size_t>(n));
      std::sort(idx.begin(), idx.end());
      run("euroc_imu_april_random" + std::to_string(n) + "_s" + std::to_string(s), pick(imu_april, idx), euroc);
    }
  // Consecutive 30-frame windows (1.5 s, like cam_april) through the sequence.
  const int windows = quick ? 4 : 12;
  for (int k = 0; k < windows; ++k) {
    const size_t start = (imu_april.size() - 30) * static_cast<size_t>(k) / static_cast<size_t>(windows - 1);
    std::vector<size_t> idx;
    for (size_t i = start; i < start + 30; ++i) idx.push_back(i);
    run("euroc_imu_april_window30_at" + std::to_string(start), pick(imu_april, idx), euroc);
  }
  return 0;
}
