// The sliding-window estimator end to end in-process: generated sequences with exact ground
// truth through the real front-end (FeatureTracker) and the estimator.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>

#include "data/camera_model.h"
#include "data/formats/trajectory_io.h"
#include "data/sim/sim_sequence.h"
#include "data/sources/euroc_reader.h"
#include "tests/test_support.h"
#include "vio/estimator/sliding_window_estimator.h"
#include "vio/eval/consistency.h"
#include "vio/eval/trajectory_eval.h"
#include "vio/frontend/feature_tracker.h"

namespace adugs::vio {
namespace {

struct PipelineRun {
  data::Trajectory trajectory;
  EstimatorStats stats;
  std::vector<EstimatorState> states;                            // every output
  Eigen::Isometry3d extrinsic = Eigen::Isometry3d::Identity();  // at the end
  double time_offset_s = 0;                                      // at the end
  bool all_finite = true;
};

// What the estimator is given instead of the sequence's own calibration and default options.
struct PipelineSetup {
  EstimatorOptions options;
  std::optional<Eigen::Isometry3d> T_B_C;
  std::function<void(FrameFeatures&)> edit_features;  // between tracker and estimator
  std::function<void(const SlidingWindowEstimator&)> after_frame;  // after each addFrame
};

// Plays an EuRoC folder through tracker + estimator. edit_image may change a frame's image
// (by its index) before tracking; IMU samples for which drop_imu returns true are withheld.
PipelineRun runPipeline(const std::string& root,
                        const std::function<void(int, cv::Mat&)>& edit_image = {},
                        const std::function<bool(const data::ImuSample&)>& drop_imu = {},
                        const PipelineSetup& setup = {}) {
  data::EurocReader reader(root);
  const data::CameraModel camera(reader.camera());
  FeatureTracker tracker(FeatureTrackerOptions{}, camera);
  ImuPreintegrationOptions imu;
  imu.gyro_noise_density = reader.imuNoise().gyro_noise_density;
  imu.accel_noise_density = reader.imuNoise().accel_noise_density;
  imu.gyro_random_walk = reader.imuNoise().gyro_random_walk;
  imu.accel_random_walk = reader.imuNoise().accel_random_walk;
  // Solved to max_iterations whatever the machine's load, as playback does (the wall-clock guard
  // is for live sources): the run is deterministic, so the bounds below are not timing margins.
  EstimatorOptions options = setup.options;
  options.max_solver_time_s = std::numeric_limits<double>::infinity();
  SlidingWindowEstimator estimator(options, camera.fx(),
                                   setup.T_B_C.value_or(reader.camera().T_B_C), imu);
  PipelineRun run;
  data::Measurement m;
  int frame = 0;
  while (reader.next(m)) {
    if (m.isImu()) {
      if (!drop_imu || !drop_imu(m.imu)) estimator.addImu(m.imu);
      continue;
    }
    if (edit_image) edit_image(frame, m.frame.image);
    ++frame;
    FrameFeatures features = tracker.trackFrame(m.frame.t_ns, m.frame.image);
    if (setup.edit_features) setup.edit_features(features);
    const auto state = estimator.addFrame(features);
    if (setup.after_frame) setup.after_frame(estimator);
    if (!state) continue;
    run.states.push_back(*state);
    run.all_finite = run.all_finite && state->p_W_B.allFinite() &&
                     state->q_W_B.coeffs().allFinite() && state->v_W.allFinite();
    data::StampedPose p;
    p.t_ns = state->t_ns;
    p.p_W_B = state->p_W_B;
    p.q_W_B = state->q_W_B;
    run.trajectory.push_back(p);
  }
  run.stats = estimator.stats();
  EXPECT_EQ(run.stats.solves_cut_by_time, 0) << "a solve was stopped by the wall clock";
  run.extrinsic = estimator.extrinsic();
  run.time_offset_s = estimator.timeOffset();
  return run;
}

std::string makeSequence(const test::TempDir& tmp, const char* level, double duration_s,
                         double time_offset_s = 0.0) {
  data::SimSequenceOptions o;
  o.time_offset_s = time_offset_s;
  o.scene = "street";
  o.level = std::string(level) == "none" ? data::SimLevel::kNone : data::SimLevel::kHigh;
  o.seed = 1;
  o.duration_s = duration_s;
  o.progress = false;
  data::generateSimSequence(o, tmp.path().string());
  return tmp.path().string();
}

// The start of the real V1_01 flight (its IMU and ground truth, ../shared/data) with the room
// rendered along it through EuRoC's lens: ~4 s on the ground with the rotors running, then the
// take-off.
void makeHybridV101Sequence(const test::TempDir& tmp, double duration_s) {
  const std::filesystem::path euroc = test::sharedDataDir() / "euroc_v101_micro";
  data::SimSequenceOptions o;
  o.trajectory_path = (euroc / "groundtruth/V1_01_easy_vicon2gt.csv").string();
  o.imu_path = (euroc / "mav0/imu0/data.csv").string();
  o.calib_path = (euroc / "mav0/cam0/sensor.yaml").string();
  o.level = data::SimLevel::kNone;
  o.seed = 1;
  o.duration_s = duration_s;
  o.progress = false;
  data::generateSimSequence(o, tmp.path().string());
}

EvalResult evaluate(const data::Trajectory& est, const std::string& root) {
  return evaluateTrajectory(
      est, data::readTrajectory(root + "/mav0/state_groundtruth_estimate0/data.csv"),
      EvalOptions{});
}

// Heading error of each estimated pose against the ground truth at the same stamp: the yaw of
// R_est R_gt^T about world z, taken relative to the first pose's (the unobservable initial yaw;
// relative, so no wrap at +-180 deg). Returns max - min over the run, in degrees.
double headingErrorSpreadDeg(const data::Trajectory& est, const std::string& root) {
  const data::Trajectory gt =
      data::readTrajectory(root + "/mav0/state_groundtruth_estimate0/data.csv");
  std::map<int64_t, Eigen::Quaterniond> truth;
  for (const auto& p : gt) truth[p.t_ns] = p.q_W_B;
  std::optional<Eigen::Quaterniond> first;
  double lo = 1e9, hi = -1e9;
  for (const auto& p : est) {
    const auto it = truth.find(p.t_ns);
    if (it == truth.end()) continue;
    const Eigen::Quaterniond error = p.q_W_B * it->second.conjugate();
    if (!first) first = error;
    const Eigen::Matrix3d d = (error * first->conjugate()).toRotationMatrix();
    const double yaw = std::atan2(d(1, 0) - d(0, 1), d(0, 0) + d(1, 1)) * 180.0 / M_PI;
    lo = std::min(lo, yaw);
    hi = std::max(hi, yaw);
  }
  EXPECT_TRUE(first.has_value()) << "no estimated pose matches a ground-truth stamp";
  return hi - lo;
}

TEST(SlidingWindowEstimator, StaticStreetTracksWithinOneAndAHalfPercent) {
  test::TempDir tmp("adugs_swe_none");
  const std::string root = makeSequence(tmp, "none", 10.0);
  const PipelineRun run = runPipeline(root);
  ASSERT_TRUE(run.all_finite);
  EXPECT_EQ(run.stats.init_kind, "visual-inertial");
  EXPECT_EQ(run.stats.resets, 0) << run.stats.last_failure;
  EXPECT_GT(run.stats.keyframes, 10);
  ASSERT_GT(run.trajectory.size(), 165u) << "initialises once the window spans 1.5 s";
  const EvalResult r = evaluate(run.trajectory, root);
  std::cout << "street/none 10 s: ATE " << r.ate.translation.rmse << " m over " << r.gt_length_m
            << " m\n";
  // Measured 0.146-0.158 m over 11.4 m (1.3-1.4 %), mostly the
  // initialisation transient of a 10 s run; doc/results.md has the 60 s figures. The run is
  // deterministic: the bound fails on an accuracy regression of 7 % or more.
  EXPECT_LT(r.ate.translation.rmse, 0.015 * r.gt_length_m);
  // The window is turned back to the oldest frame's yaw after every solve; without that, solves
  // right after initialisation turned it by degrees (spread 1.3 deg here, 0.6-40 deg on 15 s
  // street runs; 0.06 deg with the correction).
  const double spread = headingErrorSpreadDeg(run.trajectory, root);
  std::cout << "heading error spread " << spread << " deg\n";
  EXPECT_LT(spread, 0.5);
}

// The real V1_01 IMU standing on the ground with its rotors running (the first 5 s of the
// flight), the room rendered along the real trajectory: nothing moves in the images, so the
// landmarks get no depth and only the IMU, the zero-velocity updates and the window's prior hold
// the state. Two directions are then unobservable from them (bias_prior_factor.h):
// - the gyro bias about gravity (the yaw rate): it drifted from 0.002 to 0.44 rad/s in 3 s and the
//   take-off that followed ran away (2.5 m ATE over a 12 s flight); at rest the gyro measures its
//   own bias, which the estimator uses;
// - the tilt with the horizontal accelerometer bias (gravity is measured as their sum): the window
//   tilted as a whole, the bias following (15 deg in 0.5 s and a reset on a TUM-VI fisheye start);
//   the static initialisation's bias is held with a sigma.
TEST(SlidingWindowEstimator, StandingStillKeepsTheGyroBiasAndTheTilt) {
  const std::filesystem::path euroc = test::sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(euroc);
  test::TempDir tmp("adugs_swe_rest");
  makeHybridV101Sequence(tmp, 5.0);
  // The bias at rest: the mean gyro rate over the 5 s (the rotors' vibration averages out).
  Eigen::Vector3d at_rest = Eigen::Vector3d::Zero();
  int samples = 0;
  int64_t t0 = -1;
  {
    data::EurocReader reader(tmp.path().string());
    for (data::Measurement m; reader.next(m);)
      if (m.isImu()) {
        at_rest += m.imu.gyro;
        ++samples;
        if (t0 < 0) t0 = m.imu.t_ns;
      }
  }
  ASSERT_GT(samples, 900);
  at_rest /= samples;
  const auto gt = data::readTrajectory(tmp.path().string() + "/mav0/state_groundtruth_estimate0/data.csv");
  ASSERT_FALSE(gt.empty());
  // Over the last 2.5 s (after the transient of the first solves): the largest distance of the
  // estimated gyro bias from the rate at rest, and the largest tilt error (the angle between the
  // estimated and the true gravity direction in the body frame: yaw-free, so no alignment).
  struct AtRest {
    double gyro_bias_error = 0, tilt_error_deg = 0;
  };
  const auto run = [&](bool gyro_at_rest, double accel_bias_sigma) {
    PipelineSetup setup;
    setup.options.gyro_bias_at_rest = gyro_at_rest;
    setup.options.static_init_accel_bias_sigma = accel_bias_sigma;
    setup.options.window_size = 15;  // as data/config/euroc.yaml and sim.yaml
    const PipelineRun run = runPipeline(tmp.path().string(), {}, {}, setup);
    EXPECT_TRUE(run.all_finite);
    EXPECT_GT(run.states.size(), 60u) << "static initialisation within the first seconds";
    AtRest r;
    size_t k = 0;
    for (const EstimatorState& s : run.states) {
      if (s.t_ns - t0 <= data::secToNs(2.5)) continue;
      r.gyro_bias_error = std::max(r.gyro_bias_error, (s.gyro_bias - at_rest).norm());
      while (k + 1 < gt.size() && gt[k + 1].t_ns <= s.t_ns) ++k;
      const Eigen::Vector3d up_est = s.q_W_B.conjugate() * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d up_true = gt[k].q_W_B.conjugate() * Eigen::Vector3d::UnitZ();
      const double tilt = std::acos(std::clamp(up_est.dot(up_true), -1.0, 1.0)) * 180.0 / M_PI;
      r.tilt_error_deg = std::max(r.tilt_error_deg, tilt);
    }
    return r;
  };
  const AtRest both = run(true, 0.05), no_gyro = run(false, 0.05), no_accel = run(true, 0.0);
  std::cout << "at rest, gyro bias error / tilt error: both " << both.gyro_bias_error << " rad/s / "
            << both.tilt_error_deg << " deg; without the gyro factor " << no_gyro.gyro_bias_error << " / "
            << no_gyro.tilt_error_deg << "; without the accelerometer bias prior " << no_accel.gyro_bias_error
            << " / " << no_accel.tilt_error_deg << "\n";
  // Measured: 0.0007 rad/s and 1.0 deg (the initialisation's own tilt error: the true horizontal
  // bias, ~0.17 m/s^2, is taken for gravity); without the gyro factor 0.82 rad/s, without the
  // accelerometer bias prior 10.4 deg.
  EXPECT_LT(both.gyro_bias_error, 0.005);
  EXPECT_LT(both.tilt_error_deg, 2.0);
}

// The heading about gravity is unobservable, so a consistent marginalisation prior holds no
// information along the turn of the whole window about z. With the Jacobians of each solve taken
// at the newest values, every marginalisation linearises the prior's frames at points other than
// where the prior was built, and the prior gains information along that turn (it then resists
// the heading corrections the images ask for). With first-estimate Jacobians the frames of the
// prior stay linearised at its points and the turn stays free.
TEST(SlidingWindowEstimator, FirstEstimateJacobiansKeepTheHeadingUnobservable) {
  test::TempDir tmp("adugs_swe_fej");
  const std::string root = makeSequence(tmp, "none", 10.0);
  struct Consistency {
    double median_yaw_information = 0, ate = 0;
  };
  const auto run = [&](bool first_estimates) {
    PipelineSetup setup;
    setup.options.first_estimate_jacobians = first_estimates;
    const PipelineRun run = runPipeline(root, {}, {}, setup);
    EXPECT_EQ(run.stats.resets, 0) << run.stats.last_failure;
    std::vector<double> info = run.stats.prior_yaw_information;
    EXPECT_GT(info.size(), 10u);
    Consistency c;
    if (!info.empty()) {
      std::nth_element(info.begin(), info.begin() + info.size() / 2, info.end());
      c.median_yaw_information = info[info.size() / 2];
    }
    const EvalResult r = evaluate(run.trajectory, root);
    c.ate = r.ate.translation.rmse;
    // Newest values: as StaticStreetTracksWithinOneAndAHalfPercent. First estimates: tracking,
    // not more (on this 10 s run they drift more, 0.24 against 0.15 m; which is better over many
    // flights is the benchmark's question, doc/results.md).
    EXPECT_LT(c.ate, (first_estimates ? 0.03 : 0.015) * r.gt_length_m);
    return c;
  };
  const Consistency fej = run(true), newest = run(false);
  std::cout << "prior's information along the yaw (median over marginalisations): first estimates "
            << fej.median_yaw_information << ", newest values " << newest.median_yaw_information
            << " rad^-2; ATE " << fej.ate << " / " << newest.ate << " m\n";
  EXPECT_LT(fej.median_yaw_information, 1e-3);
  EXPECT_GT(newest.median_yaw_information, 1.0);
}

// The window's covariance of the newest pose relative to the oldest (report_relative_covariance)
// is of the order of the errors it makes. Not consistent: on this street sequence the NEES is
// 31 (pose), 21 (position), 1.3 (yaw), the window ~5x overconfident in position (1.6-2x on the
// room sequences, doc/results.md "Consistency"); the bounds hold that, and fail when the
// covariance is taken in the wrong frame (without the turn into the oldest body frame: 191 and 94).
TEST(SlidingWindowEstimator, WindowCovarianceIsOfTheSizeOfItsErrors) {
  test::TempDir tmp("adugs_swe_nees");
  const std::string root = makeSequence(tmp, "none", 10.0);
  PipelineSetup setup;
  setup.options.report_relative_covariance = true;
  const PipelineRun run = runPipeline(root, {}, {}, setup);
  ASSERT_EQ(run.stats.resets, 0) << run.stats.last_failure;
  const ConsistencyResult c = evaluateConsistency(
      run.stats.relative_poses,
      data::readTrajectory(root + "/mav0/state_groundtruth_estimate0/data.csv"));
  std::cout << "NEES over " << c.count << " windows: pose " << c.nees_pose << ", position "
            << c.nees_position << ", yaw " << c.nees_yaw << "; within the 95 % bound "
            << c.within_95 << "\n";
  EXPECT_GT(c.count, 150u);
  EXPECT_GT(c.nees_pose, 6.0 / 2);
  EXPECT_LT(c.nees_pose, 6.0 * 10);
  EXPECT_LT(c.nees_position, 3.0 * 10);
  EXPECT_LT(c.nees_yaw, 1.0 * 4);
  EXPECT_GT(c.within_95, 0.05);
}

// solver_function_tolerance reaches the window solver: a looser one stops the solves after fewer
// steps (each still at most max_iterations), and the trajectory stays accurate.
TEST(SlidingWindowEstimator, LooserFunctionToleranceTakesFewerSolverSteps) {
  test::TempDir tmp("adugs_swe_tolerance");
  const std::string root = makeSequence(tmp, "none", 5.0);
  const auto stepsPerSolve = [&](double tolerance, double* ate) {
    PipelineSetup setup;
    setup.options.solver_function_tolerance = tolerance;
    const PipelineRun run = runPipeline(root, {}, {}, setup);
    EXPECT_EQ(run.stats.resets, 0) << run.stats.last_failure;
    *ate = evaluate(run.trajectory, root).ate.translation.rmse;
    EXPECT_GT(run.stats.solves, 50);
    return double(run.stats.solver_iterations) / std::max(1, run.stats.solves);
  };
  double ate_strict = 0, ate_loose = 0;
  const double strict = stepsPerSolve(1e-6, &ate_strict), loose = stepsPerSolve(1e-2, &ate_loose);
  std::cout << "steps per solve: " << strict << " at 1e-6 (ATE " << ate_strict << " m), " << loose
            << " at 1e-2 (ATE " << ate_loose << " m)\n";
  EXPECT_LE(strict, 8.0);
  EXPECT_LT(loose, strict - 1.0);
  EXPECT_LT(ate_loose, 2.0 * ate_strict + 0.01);
}

// After every solve the window is turned about gravity and shifted back to the oldest frame's yaw
// and position (the gauge); the marginalisation prior goes with it (moveWorldFrame). When it did
// not, the prior pulled the window back by the correction at the start of every solve, a turn
// of the whole window that the linearised reprojections refused: rejected steps, twice the
// steps per solve, and at rest (where the prior holds most of the state) a correction of
// ~20 deg back and forth at every frame.
TEST(SlidingWindowEstimator, SolvesDoNotFightTheGaugeCorrection) {
  const std::filesystem::path euroc = test::sharedDataDir() / "euroc_v101_micro";
  ADUGS_REQUIRE_SHARED(euroc);
  test::TempDir tmp("adugs_swe_gauge");
  makeHybridV101Sequence(tmp, 8.0);
  PipelineSetup setup;
  setup.options.window_size = 15;  // as data/config/euroc.yaml and sim.yaml
  const PipelineRun run = runPipeline(tmp.path().string(), {}, {}, setup);
  ASSERT_EQ(run.stats.resets, 0) << run.stats.last_failure;
  ASSERT_GT(run.stats.solves, 120);
  const double steps = double(run.stats.solver_iterations) / run.stats.solves;
  const double rejected =
      double(run.stats.solver_iterations - run.stats.solver_successful) / run.stats.solves;
  std::cout << "steps per solve " << steps << ", rejected per solve " << rejected << "\n";
  // Measured 3.7 steps and 0.15 rejected per solve; 5.7 and 0.34 with the prior left in place.
  // Deterministic (no wall-clock limit), so the bounds are not timing margins.
  EXPECT_LT(steps, 4.5);
  EXPECT_LT(rejected, 0.25);
}

// The window waits for the initialisation with init_window_size + 1 frames, then grows to
// window_size + 1 (an SfM over a long window of walking people started at a fifth of the scale:
// doc/history.md, "The initialisation window").
TEST(SlidingWindowEstimator, InitialisesOnItsOwnWindowThenGrowsToTheFullOne) {
  test::TempDir tmp("adugs_swe_init_window");
  const std::string root = makeSequence(tmp, "none", 5.0);
  PipelineSetup setup;
  setup.options.window_size = 15;
  setup.options.init_window_size = 10;
  int largest_before = 0, largest_after = 0, at_init = 0;
  setup.after_frame = [&](const SlidingWindowEstimator& e) {
    if (!e.initialized()) {
      largest_before = std::max(largest_before, e.windowFrames());
    } else {
      if (at_init == 0) at_init = e.windowFrames();
      largest_after = std::max(largest_after, e.windowFrames());
    }
  };
  const PipelineRun run = runPipeline(root, {}, {}, setup);
  EXPECT_EQ(run.stats.init_kind, "visual-inertial");
  EXPECT_EQ(run.stats.resets, 0) << run.stats.last_failure;
  // Between frames the window holds one frame less than during the solve (the slide follows it):
  // init_window_size while waiting (filled, then thinned and slid for the SfM's 1.5 s span), then
  // window_size once initialised.
  EXPECT_EQ(largest_before, 10);
  EXPECT_LE(at_init, 11);
  EXPECT_EQ(largest_after, 15);
  const EvalResult r = evaluate(run.trajectory, root);
  EXPECT_LT(r.ate.translation.rmse, 0.015 * r.gt_length_m);
}

TEST(SlidingWindowEstimator, BlackoutResetsCleanlyAndReinitialises) {
  test::TempDir tmp("adugs_swe_blackout");
  const std::string root = makeSequence(tmp, "none", 8.0);
  // Frames 60..69 (3.0-3.5 s) are black: no features -> failure -> reset at the first of them
  // (few_features_max_s 0; the default rides through a blackout this short, next test), then
  // re-initialise.
  const auto blackout = [](int frame, cv::Mat& image) {
    if (frame >= 60 && frame < 70) image.setTo(0);
  };
  PipelineSetup at_once;
  at_once.options.few_features_max_s = 0;
  const PipelineRun run = runPipeline(root, blackout, {}, at_once);
  ASSERT_TRUE(run.all_finite);
  EXPECT_GE(run.stats.resets, 1);
  // The IMU carried the last state through the blackout and the new window was placed there: one
  // trajectory, as accurate as without the blackout's reset. Without it (option 0) the new window
  // starts again at the origin with its own heading, and the two pieces do not fit one alignment.
  EXPECT_EQ(run.stats.resets_continued, run.stats.resets);
  const EvalResult continued = evaluate(run.trajectory, root);
  const double continued_m = continued.ate.translation.rmse;
  PipelineSetup restart = at_once;
  restart.options.reset_dead_reckoning_max_s = 0;
  const PipelineRun restarted = runPipeline(root, blackout, {}, restart);
  EXPECT_EQ(restarted.stats.resets_continued, 0);
  const double restarted_m = evaluate(restarted.trajectory, root).ate.translation.rmse;
  // Measured 0.146 m over 9.1 m (1.6 %; 0.092 m before the prior moved with the gauge correction,
  // doc/estimator.md "Gauge": over seeds 2-7 of the same test the two are within each other's
  // spread, 1.03x in geometric mean); restarted 1.7 m.
  EXPECT_LT(continued_m, 0.02 * continued.gt_length_m) << "restarted: " << restarted_m;
  EXPECT_GT(restarted_m, 5 * continued_m);
  EXPECT_NE(run.stats.last_failure.find("too few tracked features"), std::string::npos)
      << run.stats.last_failure;
  // Poses resume after the blackout (re-initialised), none emitted during it.
  int after = 0;
  for (const auto& p : run.trajectory) {
    const double t = data::nsToSec(p.t_ns - run.trajectory.front().t_ns);
    EXPECT_FALSE(t > 3.0 && t < 3.45) << "pose emitted during the blackout at " << t;
    after += t > 4.0;
  }
  EXPECT_GT(after, 40);
}

// The same 0.5 s blackout with the default few_features_max_s (1 s): no reset; the window rides
// through on the IMU (a pose for every frame, the blackout's included) and picks up the new
// features after it, as accurate as the run without a blackout. A 1.5 s blackout still resets,
// 1 s into it.
TEST(SlidingWindowEstimator, AShortBlackoutIsRiddenThroughOnTheImu) {
  test::TempDir tmp("adugs_swe_ride");
  const std::string root = makeSequence(tmp, "none", 8.0);
  const auto blackout = [](int first, int end) {
    return [first, end](int frame, cv::Mat& image) {
      if (frame >= first && frame < end) image.setTo(0);
    };
  };
  ASSERT_EQ(EstimatorOptions{}.few_features_max_s, 1.0);
  const PipelineRun clear = runPipeline(root);
  const PipelineRun run = runPipeline(root, blackout(60, 70));
  ASSERT_TRUE(run.all_finite);
  EXPECT_EQ(run.stats.resets, 0) << run.stats.last_failure;
  int during = 0;
  for (const auto& p : run.trajectory) {
    const double t = data::nsToSec(p.t_ns - run.trajectory.front().t_ns);
    during += t > 3.0 && t < 3.45;
  }
  EXPECT_GE(during, 8) << "a pose per blacked-out frame";
  const EvalResult r = evaluate(run.trajectory, root);
  const double clear_m = evaluate(clear.trajectory, root).ate.translation.rmse;
  EXPECT_LT(r.ate.translation.rmse, 0.02 * r.gt_length_m);
  EXPECT_LT(r.ate.translation.rmse, 1.5 * clear_m) << "without the blackout " << clear_m;

  const PipelineRun longer = runPipeline(root, blackout(60, 90));
  EXPECT_EQ(longer.stats.resets, 1);
  EXPECT_NE(longer.stats.last_failure.find("for 1000 ms"), std::string::npos) << longer.stats.last_failure;
}

// A 0.4 s hole in the IMU stream (3.0-3.4 s): integrating across it would invent the motion, so
// the estimator resets at the first frame after the hole, emits no pose for frames inside it,
// and re-initialises.
TEST(SlidingWindowEstimator, ImuGapResetsAndReinitialises) {
  test::TempDir tmp("adugs_swe_imugap");
  const std::string root = makeSequence(tmp, "none", 7.0);
  int64_t t0 = -1;
  const PipelineRun run = runPipeline(root, {}, [&](const data::ImuSample& s) {
    if (t0 < 0) t0 = s.t_ns;
    const double t = data::nsToSec(s.t_ns - t0);
    return t > 3.0 && t < 3.4;
  });
  ASSERT_TRUE(run.all_finite);
  EXPECT_GE(run.stats.resets, 1);
  EXPECT_GE(run.stats.frames_without_imu, 6);  // frames 3.10 .. 3.35 s (3.05 is within 50 ms)
  int during = 0, after = 0;
  for (const auto& p : run.trajectory) {
    const double t = data::nsToSec(p.t_ns - t0);
    during += t > 3.06 && t < 3.4;
    after += t > 5.0;
  }
  EXPECT_EQ(during, 0);
  EXPECT_GT(after, 30) << "re-initialised after the gap (" << run.stats.last_failure << ")";
}

double rotationDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle() * 180.0 / M_PI;
}

// A rig calibrated 2 degrees and 3.7 cm off. With estimate_extrinsic the window pulls the
// camera-IMU rotation back to the truth; the translation, barely observable in 10 s of this
// motion, is held near the calibration by its prior (it is calibrated offline: adugs calib).
TEST(SlidingWindowEstimator, OnlineExtrinsicCorrectsAWrongCalibrationRotation) {
  test::TempDir tmp("adugs_swe_extrinsic");
  const std::string root = makeSequence(tmp, "none", 10.0);
  const Eigen::Isometry3d truth = data::EurocReader(root).camera().T_B_C;
  Eigen::Isometry3d wrong = truth;
  wrong.linear() =
      truth.linear() * Eigen::AngleAxisd(2.0 * M_PI / 180.0, Eigen::Vector3d(1, 1, 0).normalized())
                           .toRotationMatrix();
  wrong.translation() += Eigen::Vector3d(0.03, -0.02, 0.01);
  PipelineSetup setup;
  setup.T_B_C = wrong;
  const PipelineRun fixed = runPipeline(root, {}, {}, setup);
  setup.options.estimate_extrinsic = true;
  const PipelineRun run = runPipeline(root, {}, {}, setup);
  ASSERT_TRUE(run.all_finite);
  EXPECT_EQ(run.stats.resets, 0) << run.stats.last_failure;
  const double rot_after = rotationDeg(run.extrinsic, truth);
  const double moved = (run.extrinsic.translation() - wrong.translation()).norm();
  const double ate_fixed = evaluate(fixed.trajectory, root).ate.translation.rmse;
  const EvalResult r = evaluate(run.trajectory, root);
  std::cout << "extrinsic rotation error 2 -> " << rot_after << " deg, translation moved " << moved
            << " m; ATE " << ate_fixed << " m (fixed, wrong) -> " << r.ate.translation.rmse
            << " m (estimated) over " << r.gt_length_m << " m\n";
  EXPECT_LT(rot_after, 0.5);
  EXPECT_LT(moved, 0.02);
  EXPECT_LT(r.ate.translation.rmse, 0.8 * ate_fixed);  // measured 0.157 vs 0.303 m
}

// Images stamped 5 ms early (Kalibr's timeshift_cam_imu = +5 ms: the image stamped t shows the
// scene at IMU time t + 5 ms). Started from td = 0, the window's estimate converges to the truth,
// and the poses, stamped on the IMU clock, line up with the ground truth.
TEST(SlidingWindowEstimator, OnlineTimeOffsetRecoversAFiveMillisecondShift) {
  test::TempDir tmp("adugs_swe_td");
  const std::string root = makeSequence(tmp, "none", 15.0, 0.005);
  PipelineSetup setup;
  const PipelineRun fixed = runPipeline(root, {}, {}, setup);
  setup.options.estimate_time_offset = true;
  const PipelineRun run = runPipeline(root, {}, {}, setup);
  ASSERT_TRUE(run.all_finite);
  EXPECT_EQ(run.stats.resets, 0) << run.stats.last_failure;
  const double ate_fixed = evaluate(fixed.trajectory, root).ate.translation.rmse;
  const EvalResult r = evaluate(run.trajectory, root);
  std::cout << "time offset 0 -> " << run.time_offset_s * 1e3 << " ms (truth 5 ms); ATE "
            << ate_fixed << " m (td fixed at 0) -> " << r.ate.translation.rmse << " m\n";
  EXPECT_NEAR(run.time_offset_s, 0.005, 0.001);
  EXPECT_LT(r.ate.translation.rmse, ate_fixed);
}

// One feature in five slides off its 3-D point by 1 px per frame (as a track caught on an
// unmasked mover or a depth edge would). The robust loss alone lets them bend the window; the
// reprojection-error rejection removes them and keeps their ids out while they stay tracked.
TEST(SlidingWindowEstimator, RejectsLandmarksThatSlideOffTheirPoint) {
  test::TempDir tmp("adugs_swe_outliers");
  const std::string root = makeSequence(tmp, "none", 15.0);
  const double fx = data::EurocReader(root).camera().fx;
  PipelineSetup setup;
  const PipelineRun clean = runPipeline(root, {}, {}, setup);
  setup.edit_features = [fx](FrameFeatures& f) {
    for (size_t k = 0; k < f.size(); ++k)
      if (f.ids[k] % 5 == 0) f.normalized[k].x() += 1.0 * (f.track_counts[k] - 1) / fx;
  };
  const PipelineRun kept = [&] {
    PipelineSetup off = setup;
    off.options.outlier_reprojection_px = 0;
    return runPipeline(root, {}, {}, off);
  }();
  const PipelineRun run = runPipeline(root, {}, {}, setup);
  ASSERT_TRUE(run.all_finite);
  EXPECT_EQ(run.stats.resets, 0) << run.stats.last_failure;
  EXPECT_EQ(kept.stats.outliers_rejected, 0);
  const double ate_clean = evaluate(clean.trajectory, root).ate.translation.rmse;
  const double ate_kept = evaluate(kept.trajectory, root).ate.translation.rmse;
  const double ate = evaluate(run.trajectory, root).ate.translation.rmse;
  std::cout << "sliding features: ATE " << ate_kept << " m kept, " << ate << " m rejected ("
            << run.stats.outliers_rejected << " landmarks); clean " << ate_clean << " m ("
            << clean.stats.outliers_rejected << " rejected)\n";
  // Measured: 0.206 m kept, 0.066 m rejected (44 landmarks: a rejected id stays out while it is
  // tracked, so each sliding track counts once), 0.120 m on the clean features.
  EXPECT_GT(run.stats.outliers_rejected, 20);
  EXPECT_LT(ate, 0.6 * ate_kept);
  EXPECT_LT(ate, 1.5 * ate_clean);
}

// An estimate leaving +-max_time_offset_s means the window has gone wrong: the estimator resets,
// re-initialises with td back at the calibrated value and never emits a non-finite pose. Here the
// true 5 ms offset itself lies beyond a 3 ms bound.
TEST(SlidingWindowEstimator, TimeOffsetBeyondItsBoundResetsTheWindow) {
  test::TempDir tmp("adugs_swe_td_reset");
  const std::string root = makeSequence(tmp, "none", 12.0, 0.005);
  PipelineSetup setup;
  setup.options.estimate_time_offset = true;
  setup.options.max_time_offset_s = 0.003;
  const PipelineRun run = runPipeline(root, {}, {}, setup);
  ASSERT_TRUE(run.all_finite);
  ASSERT_GE(run.stats.resets, 1);
  EXPECT_NE(run.stats.last_failure.find("time offset"), std::string::npos) << run.stats.last_failure;
  EXPECT_LT(std::abs(run.time_offset_s), 0.003);
  ASSERT_FALSE(run.trajectory.empty());
  // Poses stop at a reset and come back once the window has re-initialised.
  size_t after_gap = 0;
  for (size_t k = 1; k < run.trajectory.size(); ++k)
    if (run.trajectory[k].t_ns - run.trajectory[k - 1].t_ns > 200'000'000) after_gap = k;
  EXPECT_GT(after_gap, 0u) << "no pose after a reset";
}

TEST(SlidingWindowEstimator, AccelNoiseInflationScalesOnlyTheAccelerometerDensity) {
  ImuPreintegrationOptions imu;  // EuRoC's ADIS16448 figures
  EstimatorOptions options;
  EXPECT_DOUBLE_EQ(SlidingWindowEstimator(options, 460.0, Eigen::Isometry3d::Identity(), imu)
                       .imuOptions()
                       .accel_noise_density,
                   imu.accel_noise_density);  // 1 by default: the calibration as it is
  options.accel_noise_inflation = 4.0;
  const SlidingWindowEstimator e(options, 460.0, Eigen::Isometry3d::Identity(), imu);
  EXPECT_DOUBLE_EQ(e.imuOptions().accel_noise_density, 4.0 * 2.0e-3);
  EXPECT_DOUBLE_EQ(e.imuOptions().gyro_noise_density, imu.gyro_noise_density);
  EXPECT_DOUBLE_EQ(e.imuOptions().accel_random_walk, imu.accel_random_walk);
  EXPECT_DOUBLE_EQ(e.imuOptions().gyro_random_walk, imu.gyro_random_walk);
  options.accel_noise_inflation = 0.0;
  EXPECT_THROW(SlidingWindowEstimator(options, 460.0, Eigen::Isometry3d::Identity(), imu),
               std::invalid_argument);
}

TEST(SlidingWindowEstimator, RejectsBadInput) {
  ImuPreintegrationOptions imu;
  EstimatorOptions options;
  SlidingWindowEstimator e(options, 460.0, Eigen::Isometry3d::Identity(), imu);
  data::ImuSample s;
  s.t_ns = 100;
  s.accel = Eigen::Vector3d(0, 0, 9.81);
  e.addImu(s);
  EXPECT_THROW(e.addImu(s), std::invalid_argument);  // same time
  s.t_ns = 200;
  s.gyro.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(e.addImu(s), std::invalid_argument);
  FrameFeatures f;
  f.t_ns = 50;  // before the first IMU sample: ignored
  EXPECT_FALSE(e.addFrame(f).has_value());
  options.window_size = 2;
  EXPECT_THROW(SlidingWindowEstimator(options, 460.0, Eigen::Isometry3d::Identity(), imu),
               std::invalid_argument);
  EXPECT_THROW(SlidingWindowEstimator(EstimatorOptions{}, 0.0, Eigen::Isometry3d::Identity(), imu),
               std::invalid_argument);
  EstimatorOptions init_too_short;
  init_too_short.init_window_size = 6;  // below init.min_frames (8): it could never initialise
  EXPECT_THROW(SlidingWindowEstimator(init_too_short, 460.0, Eigen::Isometry3d::Identity(), imu),
               std::invalid_argument);
  EstimatorOptions far_offset;
  far_offset.time_offset_s = 0.2;  // beyond max_time_offset_s (0.1 s)
  EXPECT_THROW(SlidingWindowEstimator(far_offset, 460.0, Eigen::Isometry3d::Identity(), imu),
               std::invalid_argument);
}

}  // namespace
}  // namespace adugs::vio
