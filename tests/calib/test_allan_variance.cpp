#include "calib/imu_noise/allan_variance.h"
#include "calib/imu_noise/imu_noise_verdict.h"

#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "data/input_error.h"
#include "tests/calib/imu_noise_synthetic.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

std::vector<Eigen::Vector3d> simulate(double N, double K, double rate_hz, size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  return synth::staticImuAxes(N, K, rate_hz, n, rng);
}

TEST(AllanVariance, PureWhiteNoiseHasSlopeMinusHalf) {
  const auto x = simulate(0.01, 0.0, 100, 200000, 1);
  const AllanCurve c = allanDeviation(x, 0.01, 40);
  ASSERT_GT(c.tau.size(), 20u);
  for (size_t i = 0; i < c.tau.size(); ++i) {
    if (c.tau[i] > 20) continue;  // >= 100 independent clusters: a few % scatter
    EXPECT_NEAR(c.adev[i].x() * std::sqrt(c.tau[i]), 0.01, 0.0006) << c.tau[i];
  }
}

TEST(AllanVariance, RecoversSimulatedWhiteNoiseAndRandomWalkWithin10Percent) {
  // A gyro-like and an accelerometer-like sensor, one hour at 200 Hz.
  const double rate = 200;
  const size_t n = 720000;
  ImuRecording rec;
  rec.rate_hz = rate;
  rec.gyro = simulate(2e-3, 2e-4, rate, n, 42);
  rec.accel = simulate(2e-2, 3e-3, rate, n, 43);
  for (size_t i = 0; i < n; ++i) rec.t_ns.push_back(static_cast<int64_t>(i) * 5000000);
  const ImuNoiseResult r = estimateImuNoise(rec);
  EXPECT_NEAR(r.figures.gyro_noise_density, 2e-3, 0.1 * 2e-3);
  EXPECT_NEAR(r.figures.gyro_random_walk, 2e-4, 0.1 * 2e-4);
  EXPECT_NEAR(r.figures.accel_noise_density, 2e-2, 0.1 * 2e-2);
  EXPECT_NEAR(r.figures.accel_random_walk, 3e-3, 0.1 * 3e-3);
  EXPECT_DOUBLE_EQ(r.figures.update_rate_hz, 200);
  const cv::Mat plot = renderAllanPlot(r);
  EXPECT_EQ(plot.type(), CV_8UC3);
  EXPECT_NE(formatImuNoiseReport(r, "sim", 0.1).find("random walk"), std::string::npos);
}

TEST(AllanVariance, ShortRecordingIsAnInputError) {
  ImuRecording rec;
  rec.rate_hz = 200;
  rec.t_ns = {0, 5000000};
  rec.gyro.resize(2);
  rec.accel.resize(2);
  EXPECT_THROW(estimateImuNoise(rec), data::InputError);
}

ImuRecording simulatedStatic(double seconds, unsigned seed) {
  const double rate = 200;  // EuRoC's ADIS16448 figures
  const size_t n = static_cast<size_t>(seconds * rate);
  ImuRecording rec;
  rec.rate_hz = rate;
  rec.gyro = simulate(1.7e-4, 1.9e-5, rate, n, seed);
  rec.accel = simulate(2e-3, 3e-3, rate, n, seed + 100);
  for (size_t i = 0; i < n; ++i) rec.t_ns.push_back(static_cast<int64_t>(i) * 5000000);
  return rec;
}

// The documented verdicts of `adugs calib imu` by length (EuRoC-like noise, crossover of the
// gyro's white noise and random walk at sqrt(3) N / K = 15.5 s): 20 min shows the random walk (ok),
// 2 min does not (weak: K rests on a few long clusters), 20 s cannot reach tau = 3 s (failed).
TEST(ImuNoiseVerdict, VerdictFollowsTheRecordingLength) {
  const ImuNoiseResult ok = estimateImuNoise(simulatedStatic(1200, 5));
  EXPECT_GT(randomWalkVisibility(ok.gyro, ok.duration_s), 5);
  EXPECT_EQ(judgeImuNoise(ok).verdict, Verdict::kOk) << formatVerdict(judgeImuNoise(ok), "");
  EXPECT_NEAR(ok.figures.gyro_random_walk, 1.9e-5, 0.2 * 1.9e-5);

  const ImuNoiseResult two_min = estimateImuNoise(simulatedStatic(120, 6));
  const CalibrationVerdict weak = judgeImuNoise(two_min);
  EXPECT_EQ(weak.verdict, Verdict::kWeak) << formatVerdict(weak, "");
  EXPECT_TRUE(weak.has("random walk"));
  EXPECT_NE(formatVerdict(weak, "imu.yaml").find("gyroscope"), std::string::npos);
  EXPECT_NEAR(two_min.figures.gyro_noise_density, 1.7e-4, 0.05 * 1.7e-4);  // N is fine already

  const CalibrationVerdict failed = judgeImuNoise(estimateImuNoise(simulatedStatic(20, 7)));
  EXPECT_EQ(failed.verdict, Verdict::kFailed);
  EXPECT_TRUE(failed.has("duration"));
}

// randomWalkVisibility by hand: N = 1e-3, K = 1e-4 cross at sqrt(3) * 10 s; 1732 s of data ->
// longest cluster 173.2 s = 10 x the crossover.
TEST(ImuNoiseVerdict, RandomWalkVisibilityHandWorked) {
  SensorNoise n;
  n.white = 1e-3;
  n.random_walk = 1e-4;
  EXPECT_NEAR(randomWalkVisibility(n, 1000 * std::sqrt(3.0)), 10, 1e-9);
  n.random_walk = 0;
  EXPECT_EQ(randomWalkVisibility(n, 1e6), 0);
  n.white = 0;
  n.random_walk = 1e-4;
  EXPECT_TRUE(std::isinf(randomWalkVisibility(n, 100)));
}

// The shared imu_april IMU is a 72 s calibration motion: its Allan curve is the motion's
// (0.3 rad/s, 1.5 m/s^2 at tau = 1 s), so the verdict is failed, with exit code 3 and no imu.yaml.
TEST(ImuNoiseVerdict, MovingRecordingFails) {
  const auto path = test::sharedDataDir() / "euroc_calib_aprilgrid" / "imu_april" / "imu0.csv";
  ADUGS_REQUIRE_SHARED(path);
  const CalibrationVerdict v = judgeImuNoise(estimateImuNoise(readImuCsv(path.string())));
  EXPECT_EQ(v.verdict, Verdict::kFailed);
  EXPECT_TRUE(v.has("not static"));
  if (!std::filesystem::exists(ADUGS_BINARY)) ADUGS_SKIP_OR_FAIL("adugs not built at " << ADUGS_BINARY);
  test::TempDir tmp("adugs_allan");
  std::string out;
  EXPECT_EQ(test::runAdugs("calib imu --imu " + path.string() + " --out " + tmp.path().string(), &out), 3)
      << out;
  EXPECT_NE(out.find("the IMU moved"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(tmp / "imu.yaml"));
}

TEST(AllanVariance, ReadsTheEurocImuCsv) {
  const auto path = test::sharedDataDir() / "euroc_calib_aprilgrid" / "imu_april" / "imu0.csv";
  ADUGS_REQUIRE_SHARED(path);
  const ImuRecording rec = readImuCsv(path.string());
  EXPECT_EQ(rec.t_ns.size(), 14374u);
  EXPECT_NEAR(rec.rate_hz, 200, 1);
  EXPECT_NEAR(rec.gyro[0].x(), 0.014661, 1e-12);
  EXPECT_NEAR(rec.accel[0].x(), 9.365351, 1e-12);
}

}  // namespace
}  // namespace adugs::calib
