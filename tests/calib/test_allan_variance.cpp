#include "calib/allan_variance.h"

#include <random>

#include <gtest/gtest.h>

#include "data/input_error.h"
#include "tests/test_support.h"

namespace adugs::calib {
namespace {

// White noise of density N plus a bias random walk of density K, sampled at rate_hz, per axis.
std::vector<Eigen::Vector3d> simulate(double N, double K, double rate_hz, size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const double dt = 1.0 / rate_hz;
  std::vector<Eigen::Vector3d> out(n);
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    bias += K * std::sqrt(dt) * Eigen::Vector3d(g(rng), g(rng), g(rng));
    out[i] = bias + N / std::sqrt(dt) * Eigen::Vector3d(g(rng), g(rng), g(rng));
  }
  return out;
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
