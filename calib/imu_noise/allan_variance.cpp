#include "calib/imu_noise/allan_variance.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

#include "calib/text_format.h"
#include "data/formats/imu_csv.h"
#include "data/input_error.h"

namespace adugs::calib {
namespace {

const double kInstabilityFactor = 2.0 * std::log(2.0) / M_PI;

}  // namespace

ImuRecording readImuCsv(const std::string& path) {
  ImuRecording rec;
  for (const data::ImuSample& s : data::readEurocImuCsv(path)) {
    rec.t_ns.push_back(s.t_ns);
    rec.gyro.push_back(s.gyro);
    rec.accel.push_back(s.accel);
  }
  if (rec.t_ns.size() >= 2) {
    std::vector<int64_t> dt(rec.t_ns.size() - 1);
    for (size_t i = 1; i < rec.t_ns.size(); ++i) dt[i - 1] = rec.t_ns[i] - rec.t_ns[i - 1];
    std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
    rec.rate_hz = 1e9 / static_cast<double>(dt[dt.size() / 2]);
  }
  return rec;
}

AllanCurve allanDeviation(const std::vector<Eigen::Vector3d>& samples, double dt, int points) {
  AllanCurve out;
  const size_t n = samples.size();
  if (n < 8 || !(dt > 0)) return out;
  // theta = running integral; cluster averages are differences of it.
  std::vector<Eigen::Vector3d> theta(n + 1, Eigen::Vector3d::Zero());
  for (size_t i = 0; i < n; ++i) theta[i + 1] = theta[i] + samples[i] * dt;
  const size_t m_max = n / 10;
  std::vector<size_t> sizes;
  const int p = std::max(2, points);
  for (int i = 0; i < p; ++i) {
    const size_t m = static_cast<size_t>(
        std::llround(std::pow(double(m_max), double(i) / (p - 1))));
    if (m >= 1 && (sizes.empty() || m > sizes.back())) sizes.push_back(m);
  }
  for (size_t m : sizes) {
    const double tau = m * dt;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const size_t count = n + 1 - 2 * m;
    for (size_t k = 0; k < count; ++k)
      sum += (theta[k + 2 * m] - 2 * theta[k + m] + theta[k]).cwiseAbs2();
    const Eigen::Vector3d avar = sum / (2.0 * tau * tau * double(count));
    out.tau.push_back(tau);
    out.adev.push_back(avar.cwiseSqrt());
    out.clusters.push_back(static_cast<int>(count));
  }
  return out;
}

AxisFit fitAllan(const std::vector<double>& tau, const std::vector<double>& adev,
                 const std::vector<double>& independent) {
  // AVAR = a / tau + c tau with a, c >= 0, in relative error, each point weighted by its
  // confidence: the relative error of an Allan variance from n independent clusters is about
  // 1 / sqrt(n / 2), so the long-tau points (few clusters) do not dominate. A flat
  // bias-instability term is left out of the fit: it trades off against the random walk and
  // pulls K down; B is read from the minimum of the curve instead.
  AxisFit best;
  double best_cost = -1;
  for (int mask = 1; mask < 4; ++mask) {
    const bool use_a = mask & 1, use_c = mask & 2;
    const int cols = use_a + use_c;
    Eigen::MatrixXd A(tau.size(), cols);
    Eigen::VectorXd y(tau.size());
    for (size_t i = 0; i < tau.size(); ++i) {
      const double avar = adev[i] * adev[i];
      const double n = independent.empty() ? 2.0 : std::max(independent[i], 2.0);
      const double w = avar > 0 ? std::sqrt(0.5 * n) / avar : 0.0;
      int c = 0;
      if (use_a) A(i, c++) = w / tau[i];
      if (use_c) A(i, c++) = w * tau[i];
      y(i) = avar * w;
    }
    const Eigen::VectorXd x = A.colPivHouseholderQr().solve(y);
    if ((x.array() < 0).any() || !x.allFinite()) continue;
    const double cost = (A * x - y).squaredNorm();
    if (best_cost >= 0 && cost >= best_cost) continue;
    best_cost = cost;
    int c = 0;
    best.white = use_a ? std::sqrt(x(c++)) : 0.0;
    best.random_walk = use_c ? std::sqrt(3.0 * x(c)) : 0.0;
  }
  double min_dev = 0;
  for (size_t i = 0; i < adev.size(); ++i)
    if (i == 0 || adev[i] < min_dev) min_dev = adev[i];
  best.instability = min_dev / std::sqrt(kInstabilityFactor);
  return best;
}

namespace {

SensorNoise analyse(const std::vector<Eigen::Vector3d>& samples, double dt, int points) {
  SensorNoise s;
  s.curve = allanDeviation(samples, dt, points);
  // Independent clusters behind each point: the recording length over the cluster time.
  std::vector<double> independent;
  const double length = samples.size() * dt;
  for (double tau : s.curve.tau) independent.push_back(length / tau - 1.0);
  for (int a = 0; a < 3; ++a) {
    std::vector<double> dev;
    for (const auto& v : s.curve.adev) dev.push_back(v[a]);
    s.axis[a] = fitAllan(s.curve.tau, dev, independent);
    s.white += s.axis[a].white / 3;
    s.random_walk += s.axis[a].random_walk / 3;
  }
  return s;
}

}  // namespace

ImuNoiseResult estimateImuNoise(const ImuRecording& rec, const AllanOptions& options) {
  if (rec.t_ns.size() < 1000 || !(rec.rate_hz > 0))
    throw data::InputError("", 0, "samples",
                           "an Allan analysis needs a long static recording; got " +
                               std::to_string(rec.t_ns.size()) + " samples (need >= 1000, "
                               "ideally hours)");
  ImuNoiseResult r;
  const double dt = 1.0 / rec.rate_hz;
  r.samples = rec.t_ns.size();
  r.duration_s = (rec.t_ns.back() - rec.t_ns.front()) * 1e-9;
  r.gyro = analyse(rec.gyro, dt, options.points);
  r.accel = analyse(rec.accel, dt, options.points);
  r.figures.gyro_noise_density = r.gyro.white;
  r.figures.gyro_random_walk = r.gyro.random_walk;
  r.figures.accel_noise_density = r.accel.white;
  r.figures.accel_random_walk = r.accel.random_walk;
  r.figures.update_rate_hz = rec.rate_hz;
  return r;
}

std::string formatImuNoiseReport(const ImuNoiseResult& r, const std::string& input,
                                 double seconds, const std::string& verdict_block) {
  std::string s = "adugs calib imu\n";
  s += "  input     " + input + "\n";
  s += strprintf("  samples   %zu over %.1f s (%.1f Hz); analysis %.2f s\n\n", r.samples,
                 r.duration_s, r.figures.update_rate_hz, seconds);
  if (!verdict_block.empty()) s += verdict_block + "\n";
  auto sensor = [&](const char* name, const SensorNoise& n, const char* wu, const char* ku) {
    s += strprintf("%s                 white noise N [%s]   bias instability B   random walk K [%s]\n",
                   name, wu, ku);
    const char* axes = "xyz";
    for (int a = 0; a < 3; ++a)
      s += strprintf("  %c axis         %12.4e            %12.4e        %12.4e\n", axes[a],
                     n.axis[a].white, n.axis[a].instability, n.axis[a].random_walk);
    s += strprintf("  mean (imu.yaml)%12.4e                                %12.4e\n\n", n.white,
                   n.random_walk);
  };
  sensor("gyroscope", r.gyro, "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)");
  sensor("accelerometer", r.accel, "m/s^2/sqrt(Hz)", "m/s^3/sqrt(Hz)");
  s += "Kalibr wants these continuous-time figures; inflate them (x2..x10) for a moving rig.\n";
  return s;
}

cv::Mat renderAllanPlot(const ImuNoiseResult& r) {
  const int W = 1400, H = 620, pad = 70, panel = (W - 3 * pad) / 2;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar axis_colour[3] = {{40, 40, 220}, {40, 160, 40}, {200, 80, 40}};
  auto drawPanel = [&](int x0, const SensorNoise& n, const std::string& title) {
    const int y0 = pad, h = H - 2 * pad;
    cv::rectangle(img, cv::Rect(x0, y0, panel, h), cv::Scalar(0, 0, 0), 1);
    if (n.curve.tau.empty()) return;
    double lo = 1e300, hi = -1e300;
    for (const auto& v : n.curve.adev)
      for (int a = 0; a < 3; ++a)
        if (v[a] > 0) {
          lo = std::min(lo, std::log10(v[a]));
          hi = std::max(hi, std::log10(v[a]));
        }
    lo = std::floor(lo - 0.2);
    hi = std::ceil(hi + 0.2);
    const double t_lo = std::floor(std::log10(n.curve.tau.front()));
    const double t_hi = std::ceil(std::log10(n.curve.tau.back()));
    auto px = [&](double tau, double dev) {
      const double u = (std::log10(tau) - t_lo) / (t_hi - t_lo);
      const double v = (std::log10(std::max(dev, 1e-300)) - lo) / (hi - lo);
      return cv::Point(int(x0 + u * panel), int(y0 + h - v * h));
    };
    for (double d = t_lo; d <= t_hi; d += 1) {
      cv::line(img, px(std::pow(10, d), std::pow(10, lo)), px(std::pow(10, d), std::pow(10, hi)),
               cv::Scalar(225, 225, 225), 1);
      cv::putText(img, strprintf("1e%+d", int(d)), px(std::pow(10, d), std::pow(10, lo)) + cv::Point(-18, 20),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    for (double d = lo; d <= hi; d += 1) {
      cv::line(img, px(std::pow(10, t_lo), std::pow(10, d)), px(std::pow(10, t_hi), std::pow(10, d)),
               cv::Scalar(225, 225, 225), 1);
      cv::putText(img, strprintf("1e%+d", int(d)), px(std::pow(10, t_lo), std::pow(10, d)) + cv::Point(-62, 5),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    for (int a = 0; a < 3; ++a) {
      for (size_t i = 0; i + 1 < n.curve.tau.size(); ++i)
        cv::line(img, px(n.curve.tau[i], n.curve.adev[i][a]),
                 px(n.curve.tau[i + 1], n.curve.adev[i + 1][a]), axis_colour[a], 2, cv::LINE_AA);
    }
    // Fitted lines of the mean figures, and their read-out points at tau = 1 and 3 s.
    const double ta = n.curve.tau.front(), tb = n.curve.tau.back();
    const cv::Rect frame(x0, y0, panel, h);
    auto clipped = [&](cv::Point a, cv::Point b, const cv::Scalar& colour) {
      if (cv::clipLine(frame, a, b)) cv::line(img, a, b, colour, 1, cv::LINE_AA);
    };
    if (n.white > 0)
      clipped(px(ta, n.white / std::sqrt(ta)), px(tb, n.white / std::sqrt(tb)), cv::Scalar(0, 0, 0));
    if (n.random_walk > 0)
      clipped(px(ta, n.random_walk * std::sqrt(ta / 3)), px(tb, n.random_walk * std::sqrt(tb / 3)),
              cv::Scalar(120, 120, 120));
    cv::circle(img, px(1.0, n.white), 5, cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
    cv::circle(img, px(3.0, n.random_walk), 5, cv::Scalar(120, 120, 120), 2, cv::LINE_AA);
    cv::putText(img, title, cv::Point(x0, y0 - 30), cv::FONT_HERSHEY_SIMPLEX, 0.55,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    cv::putText(img, strprintf("N = %.3e (slope -1/2 at tau=1s), K = %.3e (slope +1/2 at tau=3s)",
                               n.white, n.random_walk),
                cv::Point(x0, y0 - 10), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    cv::putText(img, "tau [s]   (x red, y green, z blue)", cv::Point(x0 + panel / 2 - 120, y0 + h + 45),
                cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  };
  drawPanel(pad + 10, r.gyro, "gyroscope Allan deviation [rad/s]");
  drawPanel(2 * pad + panel + 10, r.accel, "accelerometer Allan deviation [m/s^2]");
  return img;
}

}  // namespace adugs::calib
