#include "vio/estimator/sliding_window_estimator.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "data/elapsed_time.h"
#include "vio/estimator/bias_prior_factor.h"
#include "vio/estimator/imu_factor.h"
#include "vio/estimator/pose_manifold.h"
#include "vio/estimator/pose_prior_factor.h"
#include "vio/estimator/reprojection_factor.h"
#include "vio/estimator/scalar_prior_factor.h"
#include "vio/estimator/window_solver.h"
#include "vio/estimator/zero_velocity_factor.h"
#include "vio/imu/so3.h"
#include "vio/init/static_initializer.h"
#include "vio/init/visual_inertial_initializer.h"

namespace adugs::vio {
namespace {

const PoseManifold kPoseManifold;

void setSpeedBias(const Eigen::Vector3d& v, const Eigen::Vector3d& ba, const Eigen::Vector3d& bg,
                  double* sb) {
  Eigen::Map<Eigen::Matrix<double, 9, 1>> x(sb);
  x << v, ba, bg;
}

bool contains(const std::vector<double*>& blocks, const double* b) {
  return std::find(blocks.begin(), blocks.end(), b) != blocks.end();
}

}  // namespace

SlidingWindowEstimator::SlidingWindowEstimator(const EstimatorOptions& options, double focal_px,
                                               const Eigen::Isometry3d& T_B_C,
                                               const ImuPreintegrationOptions& imu_options)
    : options_(options),
      focal_px_(focal_px),
      T_B_C_iso_(T_B_C),
      T_B_C_calibrated_(T_B_C),
      td_(options.time_offset_s),
      imu_options_(imu_options) {
  if (!(focal_px > 0))
    throw std::invalid_argument("SlidingWindowEstimator: focal length must be positive");
  if (!(options_.accel_noise_inflation > 0))
    throw std::invalid_argument("SlidingWindowEstimator: accel_noise_inflation must be positive");
  imu_options_.accel_noise_density *= options_.accel_noise_inflation;
  if (options_.window_size < 4 ||
      options_.init.min_frames > std::min(options_.init_window_size, options_.window_size))
    throw std::invalid_argument(
        "SlidingWindowEstimator: window_size must be >= 4, and both it and init_window_size >= init.min_frames");
  if (!(std::abs(options_.time_offset_s) < options_.max_time_offset_s))
    throw std::invalid_argument(
        "SlidingWindowEstimator: time_offset_s must lie within +-max_time_offset_s");
  setPose(T_B_C.translation(), Eigen::Quaterniond(T_B_C.rotation()), T_B_C_);
  options_.init.focal_px = focal_px;
}

void SlidingWindowEstimator::addImu(const data::ImuSample& s) {
  if (!s.gyro.allFinite() || !s.accel.allFinite())
    throw std::invalid_argument("SlidingWindowEstimator: non-finite IMU sample");
  if (!imu_.empty() && s.t_ns <= imu_.back().t_ns)
    throw std::invalid_argument("SlidingWindowEstimator: IMU samples must come in increasing time");
  imu_.push_back(s);
}

data::ImuSample SlidingWindowEstimator::imuAt(int64_t t_ns) const { return imuReadingAt(imu_, t_ns); }

std::shared_ptr<ImuPreintegration> SlidingWindowEstimator::preintegrate(
    int64_t from_ns, int64_t to_ns, const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) const {
  auto pre = std::make_shared<ImuPreintegration>(imuAt(from_ns), ba, bg, imu_options_);
  for (const data::ImuSample& s : imu_)
    if (s.t_ns > from_ns && s.t_ns < to_ns) pre->integrate(s);
  pre->integrate(imuAt(to_ns));
  return pre;
}

Eigen::Quaterniond SlidingWindowEstimator::rotationSinceLastFrame(int64_t t_ns) const {
  if (frames_.empty() || imu_.empty() || t_ns <= frames_.back()->t_ns)
    return Eigen::Quaterniond::Identity();
  const Frame& last = *frames_.back();
  return preintegrate(last.imuTimeNs(), t_ns + data::secToNs(td_), last.ba(), last.bg())->deltaQ();
}

int64_t SlidingWindowEstimator::longestImuGap(int64_t from_ns, int64_t to_ns) const {
  auto it = std::upper_bound(imu_.begin(), imu_.end(), from_ns,
                             [](int64_t t, const data::ImuSample& s) { return t < s.t_ns; });
  int64_t previous = it == imu_.begin() ? from_ns : std::prev(it)->t_ns, longest = 0;
  for (; it != imu_.end() && previous < to_ns; ++it) {
    longest = std::max(longest, std::min(it->t_ns, to_ns) - previous);
    previous = it->t_ns;
  }
  return std::max(longest, to_ns - previous);
}

Eigen::Vector3d SlidingWindowEstimator::gyroBias() const {
  return frames_.empty() ? Eigen::Vector3d::Zero() : frames_.back()->bg();
}

std::vector<Eigen::Isometry3d> SlidingWindowEstimator::cameraPoses() const {
  std::vector<Eigen::Isometry3d> T_W_C;
  for (const auto& f : frames_) {
    Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
    T_W_B.linear() = f->q().toRotationMatrix();
    T_W_B.translation() = f->p();
    T_W_C.push_back(T_W_B * T_B_C_iso_);
  }
  return T_W_C;
}

EstimatorState SlidingWindowEstimator::stateOf(const Frame& f) const {
  EstimatorState s;
  s.p_W_B = f.p();
  s.q_W_B = f.q().normalized();
  s.v_W = f.v();
  s.accel_bias = f.ba();
  s.gyro_bias = f.bg();
  s.stationary = f.stationary;
  s.t_ns = f.imuTimeNs();
  return s;
}

bool SlidingWindowEstimator::isStationary() const {
  const Frame& newest = *frames_.back();
  const int64_t window_ns = data::secToNs(options_.static_init.window_s);
  // The oldest window frame within the static window: parallax over it.
  int oldest = -1;
  for (int k = 0; k < static_cast<int>(frames_.size()); ++k)
    if (newest.t_ns - frames_[k]->t_ns <= window_ns) {
      oldest = k;
      break;
    }
  if (oldest < 0 || oldest == static_cast<int>(frames_.size()) - 1) return false;
  if (newest.t_ns - frames_[oldest]->t_ns < window_ns / 2) return false;  // too short to judge
  int common = 0;
  const double parallax_px =
      landmarks_.meanParallax(oldest, static_cast<int>(frames_.size()) - 1, &common) * focal_px_;
  if (common < 8) return false;
  std::vector<data::ImuSample> window;
  const int64_t t_end = newest.imuTimeNs();
  for (const data::ImuSample& s : imu_)
    if (s.t_ns > t_end - window_ns && s.t_ns <= t_end) window.push_back(s);
  return initializeStatic(window, parallax_px, options_.static_init).stationary;
}

void SlidingWindowEstimator::measureGyroAtRest() {
  if (frames_.size() < 2) return;
  Frame& newest = *frames_.back();
  const int64_t from = frames_[frames_.size() - 2]->imuTimeNs(), to = newest.imuTimeNs();
  std::vector<Eigen::Vector3d> rates;
  for (const data::ImuSample& s : imu_)
    if (s.t_ns > from && s.t_ns <= to) rates.push_back(s.gyro);
  const double rate_hz = rates.size() / std::max(1e-9, data::nsToSec(to - from));
  newest.has_gyro_at_rest = gyroMeanAtRest(rates, rate_hz, imu_options_.gyro_noise_density,
                                           &newest.gyro_at_rest_mean, &newest.gyro_at_rest_sigma);
}

bool SlidingWindowEstimator::tryInitialize() {
  Frame& newest = *frames_.back();
  if (newest.stationary) {
    std::vector<data::ImuSample> window;
    const int64_t window_ns = data::secToNs(options_.static_init.window_s);
    const int64_t t_end = newest.imuTimeNs();
    for (const data::ImuSample& s : imu_)
      if (s.t_ns > t_end - window_ns && s.t_ns <= t_end) window.push_back(s);
    const StaticInitResult r = initializeStatic(window, 0.0, options_.static_init);
    if (!r.stationary) return false;
    for (auto& f : frames_) {
      setPose(Eigen::Vector3d::Zero(), r.q_W_B, f->pose);
      setSpeedBias(Eigen::Vector3d::Zero(), r.accel_bias, r.gyro_bias, f->speed_bias);
      if (f->imu) f->imu->repropagate(r.accel_bias, r.gyro_bias);
    }
    // At rest tilt and horizontal accelerometer bias are one unknown: hold the bias where the
    // initialisation put it (bias_prior_factor.h); marginalised with this frame into the prior.
    holdInitialAccelBias(r.accel_bias, options_.static_init_accel_bias_sigma);
    stats_.init_kind = "static";
    if (!dead_reckoned_.empty()) continueFromDeadReckoning();
    return true;
  }
  if (static_cast<int>(frames_.size()) < options_.init.min_frames) return false;
  if (data::nsToSec(frames_.back()->t_ns - frames_.front()->t_ns) < options_.init_min_span_s)
    return false;
  std::vector<InitFrame> init_frames;
  for (const auto& f : frames_) {
    InitFrame i;
    i.t_ns = f->t_ns;
    i.ids = f->features.ids;
    i.normalized = f->features.normalized;
    i.imu_from_previous = f->imu;
    init_frames.push_back(std::move(i));
  }
  init_frames.front().imu_from_previous = nullptr;
  const InitResult r = initializeVisualInertial(init_frames, T_B_C_iso_, options_.init);
  if (!r.success) {
    stats_.last_init_failure = r.failure_reason;
    if (r.scale_relative_std > 0) ++stats_.init_refused_uncertain_scale;
    return false;
  }
  if (stats_.init_scale_relative_std < 0) stats_.init_scale_relative_std = r.scale_relative_std;
  for (size_t k = 0; k < frames_.size(); ++k) {
    Frame& f = *frames_[k];
    setPose(r.poses[k].p_W_B, r.poses[k].q_W_B, f.pose);
    setSpeedBias(r.velocities_W[k], r.accel_bias, r.gyro_bias, f.speed_bias);
    if (f.imu) f.imu->repropagate(r.accel_bias, r.gyro_bias);
  }
  // In motion the accelerometer bias and the scale trade off when the IMU accelerates little:
  // without a prior the window can move the bias by 0.2 m/s^2 and the scale by 20 % together, and
  // the marginalisation prior then keeps both (doc/estimator.md). Held near the initialisation's
  // value (zero, as VINS-Mono); marginalised with the frame.
  holdInitialAccelBias(r.accel_bias, options_.vi_init_accel_bias_sigma);
  const auto T_W_C = cameraPoses();
  for (const auto& [id, p_W] : r.landmarks_W) landmarks_.setWorldPoint(id, p_W, T_W_C);
  stats_.init_kind = "visual-inertial";
  if (!dead_reckoned_.empty()) continueFromDeadReckoning();  // host-relative depths: unchanged
  return true;
}

void SlidingWindowEstimator::thinWindow() {
  // Drop the inner frame whose neighbours are closest in time.
  int best = 1;
  int64_t best_gap = INT64_MAX;
  for (int k = 1; k + 1 < static_cast<int>(frames_.size()) - 1; ++k) {
    const int64_t gap = frames_[k + 1]->t_ns - frames_[k - 1]->t_ns;
    if (gap < best_gap) {
      best_gap = gap;
      best = k;
    }
  }
  dropFrame(best);
}

FrameFeatures SlidingWindowEstimator::timeOffsetVelocities(const FrameFeatures& features) {
  // The tracker's velocity at a frame is (pt_k - pt_k-1) / dt: it carries pt_k's own tracking
  // noise, which then correlates with the residual it corrects and biases td (street sequence,
  // truth 0: +2.4 ms; with the previous step's velocity: 0.001 ms). So each observation moves along
  // the velocity its feature had at the previous frame (zero for a feature seen twice or less).
  std::unordered_map<int64_t, Eigen::Vector2d> now;
  FrameFeatures out = features;
  for (size_t k = 0; k < out.size(); ++k) {
    now[out.ids[k]] = features.velocities[k];
    const auto it = last_velocities_.find(out.ids[k]);
    out.velocities[k] = it != last_velocities_.end() ? it->second : Eigen::Vector2d::Zero();
  }
  last_velocities_ = std::move(now);
  return out;
}

void SlidingWindowEstimator::dropOldestUninitialized() {
  frames_.pop_front();
  landmarks_.removeFrame(0, nullptr);
  frames_.front()->imu = nullptr;
  // Keep one IMU sample at or before the oldest frame.
  while (imu_.size() > 2 && imu_[1].t_ns <= frames_.front()->imuTimeNs()) imu_.pop_front();
}

std::optional<EstimatorState> SlidingWindowEstimator::addFrame(const FrameFeatures& features) {
  ++stats_.frames;
  if (imu_.empty() || features.t_ns < imu_.front().t_ns) return std::nullopt;
  if (!frames_.empty() && features.t_ns <= frames_.back()->t_ns)
    throw std::invalid_argument("SlidingWindowEstimator: frame times must increase");
  const int64_t max_gap = data::secToNs(options_.max_imu_gap_s);
  if (features.t_ns - imu_.back().t_ns > max_gap) {  // the IMU stream stopped before this frame
    ++stats_.frames_without_imu;
    if (!frames_.empty())
      reset("no IMU sample within " + std::to_string(options_.max_imu_gap_s) + " s of frame " +
                std::to_string(features.t_ns),
            false);
    return std::nullopt;
  }
  if (!frames_.empty()) {
    const int64_t gap = longestImuGap(frames_.back()->t_ns, features.t_ns);
    if (gap > max_gap) {
      // Integrating across the hole would invent the motion: start again from this frame.
      reset("IMU gap of " + std::to_string(data::nsToSec(gap)) + " s before frame " +
                std::to_string(features.t_ns),
            false);
    }
  }

  auto frame = std::make_unique<Frame>();
  frame->t_ns = features.t_ns;
  frame->td = td_;
  frame->features = features;
  if (frames_.empty()) {
    setPose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(), frame->pose);
    setSpeedBias(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                 frame->speed_bias);
  } else {
    // IMU prediction from the previous frame.
    const Frame& prev = *frames_.back();
    frame->imu = preintegrate(prev.imuTimeNs(), frame->imuTimeNs(), prev.ba(), prev.bg());
    const double T = frame->imu->sumDt();
    const Eigen::Vector3d& g = imu_options_.gravity_W;
    const Eigen::Quaterniond q_i = prev.q();
    const Eigen::Vector3d p =
        prev.p() + prev.v() * T + 0.5 * g * T * T + q_i * frame->imu->deltaP();
    const Eigen::Vector3d v = prev.v() + g * T + q_i * frame->imu->deltaV();
    setPose(p, q_i * frame->imu->deltaQ(), frame->pose);
    setSpeedBias(v, prev.ba(), prev.bg(), frame->speed_bias);
  }
  frames_.push_back(std::move(frame));
  if (!initialized_ && !dead_reckoned_.empty()) deadReckonToNewest();
  const int newest = static_cast<int>(frames_.size()) - 1;
  if (options_.estimate_time_offset)
    landmarks_.addFrame(newest, timeOffsetVelocities(features));
  else
    landmarks_.addFrame(newest, features);  // velocities unused
  frames_.back()->stationary = isStationary();
  if (frames_.back()->stationary) {
    settled_since_ns_ = features.t_ns;
    if (options_.gyro_bias_at_rest) measureGyroAtRest();
  }

  bool just_initialized = false;
  if (!initialized_) {
    if (!tryInitialize()) {
      // Same window policy as when running (so the window spans enough parallax for the SfM),
      // without marginalisation: nothing is estimated yet.
      if (static_cast<int>(frames_.size()) > std::min(options_.init_window_size, options_.window_size)) {
        const double span_s = data::nsToSec(frames_.back()->t_ns - frames_.front()->t_ns);
        if (span_s < options_.init_min_span_s)
          thinWindow();  // scale needs acceleration, acceleration needs time: spread the frames
        else if (secondNewestIsKeyframe())
          dropOldestUninitialized();
        else
          dropSecondNewest();
      }
      return std::nullopt;
    }
    initialized_ = just_initialized = true;
    if (stats_.init_t_ns < 0) stats_.init_t_ns = features.t_ns;
    settled_since_ns_ = features.t_ns;
  }

  const Eigen::Vector3d predicted_p = frames_.back()->p();
  if (!frames_.back()->stationary)  // no parallax while standing still: depths would be noise
    landmarks_.triangulate(cameraPoses(), options_.min_depth_m, options_.max_depth_m,
                           options_.min_triangulation_angle_deg * M_PI / 180.0);
  solve();
  rejectOutliers();

  std::string why;
  if (!frames_.back()->stationary && static_cast<int>(features.size()) < options_.min_tracked_features) {
    if (few_features_since_ns_ < 0) few_features_since_ns_ = features.t_ns;
    const double few_s = data::nsToSec(features.t_ns - few_features_since_ns_);
    if (few_s >= options_.few_features_max_s)
      why = "too few tracked features (" + std::to_string(features.size()) + ", fewer than " +
            std::to_string(options_.min_tracked_features) + " for " + std::to_string(static_cast<int>(std::lround(few_s * 1000))) + " ms)";
  } else {
    few_features_since_ns_ = -1;
  }
  if (why.empty() && failureDetected(just_initialized ? frames_.back()->p() : predicted_p, &why)) {
  }
  if (!why.empty()) {
    reset(why);
    return std::nullopt;
  }
  const EstimatorState state = stateOf(*frames_.back());
  last_output_ = state;
  slideWindow();
  return state;
}

std::vector<std::unique_ptr<ceres::CostFunction>> SlidingWindowEstimator::restFactors(const Frame& f) const {
  std::vector<std::unique_ptr<ceres::CostFunction>> factors;
  if (!options_.zero_velocity_updates || !f.stationary) return factors;
  factors.push_back(std::make_unique<ZeroVelocityFactor>(options_.zero_velocity_sigma));
  if (f.has_gyro_at_rest)  // measured only with options_.gyro_bias_at_rest
    factors.push_back(std::make_unique<BiasPriorFactor>(BiasPriorFactor::Bias::kGyro, f.gyro_at_rest_mean,
                                                        f.gyro_at_rest_sigma));
  return factors;
}

void SlidingWindowEstimator::holdInitialAccelBias(const Eigen::Vector3d& bias, double sigma) {
  frames_.front()->accel_bias_prior = bias;
  frames_.front()->accel_bias_prior_sigma = sigma;
}

std::unique_ptr<ceres::CostFunction> SlidingWindowEstimator::accelBiasPrior(const Frame& f) const {
  return std::make_unique<BiasPriorFactor>(BiasPriorFactor::Bias::kAccel, f.accel_bias_prior,
                                           Eigen::Vector3d::Constant(f.accel_bias_prior_sigma));
}

void SlidingWindowEstimator::solve() {
  const auto t0 = std::chrono::steady_clock::now();
  WindowSolver solver;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  ceres::HuberLoss huber(options_.huber_px);

  for (auto& f : frames_) {
    solver.addBlock(f->pose, 7, &kPoseManifold);
    solver.addChainBlock(f->speed_bias, 9);  // meets only its IMU neighbours
  }
  solver.addBlock(T_B_C_, 7, &kPoseManifold);
  const bool extrinsic_free = options_.estimate_extrinsic && !frames_.back()->stationary;
  if (extrinsic_free) {
    costs.push_back(std::make_unique<PosePriorFactor>(
        T_B_C_calibrated_.translation(), Eigen::Quaterniond(T_B_C_calibrated_.rotation()),
        options_.extrinsic_prior_sigma_m, options_.extrinsic_prior_sigma_deg * M_PI / 180.0));
    solver.addResidual(costs.back().get(), nullptr, {T_B_C_});
  } else {
    solver.setConstant(T_B_C_);
  }
  solver.addBlock(&td_, 1);
  // Standing still there is no image motion to tell the offset by.
  const bool td_free = options_.estimate_time_offset && !frames_.back()->stationary &&
                       data::nsToSec(frames_.back()->t_ns - settled_since_ns_) >=
                           options_.time_offset_warmup_s;
  if (td_free) {
    costs.push_back(
        std::make_unique<ScalarPriorFactor>(options_.time_offset_s, options_.time_offset_prior_sigma_s));
    solver.addResidual(costs.back().get(), nullptr, {&td_});
  } else {
    solver.setConstant(&td_);
  }
  if (!prior_) solver.setConstant(frames_.front()->pose);  // gauge before any prior

  for (size_t k = 1; k < frames_.size(); ++k) {
    if (!frames_[k]->imu || frames_[k]->imu->sumDt() > 10.0) continue;
    costs.push_back(std::make_unique<ImuFactor>(frames_[k]->imu));
    solver.addResidual(costs.back().get(), nullptr,
                       {frames_[k - 1]->pose, frames_[k - 1]->speed_bias, frames_[k]->pose,
                        frames_[k]->speed_bias});
  }
  for (auto& f : frames_)
    for (auto& cost : restFactors(*f)) {
      costs.push_back(std::move(cost));
      solver.addResidual(costs.back().get(), nullptr, {f->speed_bias});
    }
  for (auto& f : frames_)
    if (f->accel_bias_prior_sigma > 0) {
      costs.push_back(accelBiasPrior(*f));
      solver.addResidual(costs.back().get(), nullptr, {f->speed_bias});
    }
  const double sqrt_info = reprojectionSqrtInformation(focal_px_, options_.pixel_sigma);
  int used = 0;
  std::vector<double*> blocks;  // reused: one allocation, not one per residual
  reprojection_factors_.reuseAll();
  for (auto& [id, l] : landmarks_.landmarks()) {
    if (!l.has_depth || l.observations.size() < 2) continue;
    solver.addLandmark(&l.inverse_depth);
    const Observation& host = l.observations.front();
    for (size_t k = 1; k < l.observations.size(); ++k)
      solver.addResidual(reprojectionCost(host, l.observations[k], sqrt_info, l, &blocks), &huber,
                         blocks);
    ++used;
  }
  stats_.landmarks_in_last_solve = used;
  if (prior_) solver.setPrior(prior_.get(), options_.first_estimate_jacobians);

  // The problem is invariant to a rotation about gravity and a translation (4 unobservable
  // degrees of freedom); remember where the oldest frame was to undo drift along them.
  const Eigen::Vector3d p0_before = frames_.front()->p();
  const Eigen::Matrix3d R0_before = frames_.front()->q().toRotationMatrix();

  WindowSolverOptions so;
  so.max_iterations = options_.max_iterations;
  so.function_tolerance = options_.solver_function_tolerance;
  so.max_time_s = options_.max_solver_time_s;
  const WindowSolverSummary summary = solver.solve(so);
  ++stats_.solves;
  stats_.solver_iterations += summary.iterations;
  stats_.solver_successful += summary.successful;
  if (summary.time_limit_hit) ++stats_.solves_cut_by_time;

  for (auto& f : frames_) {
    Eigen::Map<Eigen::Quaterniond> q(f->pose + 3);
    q.normalize();
  }
  if (extrinsic_free) {
    Eigen::Map<Eigen::Quaterniond> q(T_B_C_ + 3);
    q.normalize();
    T_B_C_iso_.linear() = q.toRotationMatrix();
    T_B_C_iso_.translation() = Eigen::Vector3d(T_B_C_[0], T_B_C_[1], T_B_C_[2]);
  }
  if (options_.report_relative_covariance) recordRelativeCovariance(solver);
  // Yaw and position are unobservable; the window's linearised prior holds them only loosely (it
  // was built at older linearisation points), and solves right after initialisation rotated the
  // whole window by up to 4 deg in yaw, which every later pose inherits. So, as VINS-Mono's
  // double2vector, every solve moves the window back to the oldest frame's yaw and position
  // (15 simulated sequences: mean ATE 0.30 -> 0.22 % of the distance; doc/estimator.md).
  removeGaugeDrift(p0_before, R0_before);
  // Landmarks that ended behind their host or absurdly far lose their depth (re-triangulated
  // later).
  for (auto it = landmarks_.landmarks().begin(); it != landmarks_.landmarks().end();) {
    Landmark& l = it->second;
    if (l.has_depth &&
        (!(l.inverse_depth > 1.0 / options_.max_depth_m) || !std::isfinite(l.inverse_depth))) {
      it = landmarks_.landmarks().erase(it);
      continue;
    }
    ++it;
  }
  stats_.solve_ms.push_back(data::msSince(t0));
}

void SlidingWindowEstimator::recordRelativeCovariance(WindowSolver& solver) {
  if (frames_.size() < 2) return;
  const Eigen::MatrixXd S = solver.frameInformation();
  const Frame& from = *frames_.front();
  const Frame& to = *frames_.back();
  const int o_from = solver.tangentOffset(from.pose), o_to = solver.tangentOffset(to.pose);
  if (S.size() == 0 || o_to < 0) return;
  // Given the oldest pose: its rows and columns out of the information (where it is free).
  std::vector<int> kept;
  int to_row = -1;
  for (int i = 0; i < static_cast<int>(S.rows()); ++i) {
    if (o_from >= 0 && i >= o_from && i < o_from + 6) continue;
    if (i == o_to) to_row = static_cast<int>(kept.size());
    kept.push_back(i);
  }
  const int n = static_cast<int>(kept.size());
  Eigen::MatrixXd given(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) given(i, j) = S(kept[i], kept[j]);
  const Eigen::LLT<Eigen::MatrixXd> llt(given);
  if (llt.info() != Eigen::Success) return;
  Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(n, 6);
  unit.middleRows(to_row, 6).setIdentity();
  const Eigen::Matrix<double, 6, 6> newest = llt.solve(unit).middleRows(to_row, 6);
  // [dp in the world, dtheta on the right] of the newest pose -> dp in the oldest body frame.
  const Eigen::Matrix3d R_from = from.q().toRotationMatrix();
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Identity();
  A.topLeftCorner<3, 3>() = R_from.transpose();
  RelativePoseEstimate e;
  e.t_from_ns = from.imuTimeNs();
  e.t_to_ns = to.imuTimeNs();
  e.p_from_to = R_from.transpose() * (to.p() - from.p());
  e.q_from_to = (from.q().conjugate() * to.q()).normalized();
  e.covariance = A * newest * A.transpose();
  e.covariance = (0.5 * (e.covariance + e.covariance.transpose())).eval();
  stats_.relative_poses.push_back(e);
}

void SlidingWindowEstimator::rejectOutliers() {
  if (options_.outlier_reprojection_px <= 0) return;
  // A feature the tracker followed off its 3-D point (a depth edge, a repeated texture, a mover
  // outside the mask) pulls the window through the robust loss; with fewer than 3 frames its
  // depth alone absorbs the error, so it cannot be judged.
  const double sqrt_info = reprojectionSqrtInformation(focal_px_, options_.pixel_sigma);
  const double px_per_residual = focal_px_ / sqrt_info;
  std::vector<int64_t> outliers;
  std::vector<double*> blocks;
  reprojection_factors_.reuseAll();
  for (auto& [id, l] : landmarks_.landmarks()) {
    if (!l.has_depth || l.observations.size() < 3) continue;
    double sum_px = 0;
    for (size_t k = 1; k < l.observations.size(); ++k) {
      const ceres::CostFunction* cost =
          reprojectionCost(l.observations.front(), l.observations[k], sqrt_info, l, &blocks);
      Eigen::Vector2d r;
      if (!cost->Evaluate(blocks.data(), r.data(), nullptr)) r.setConstant(1e9);
      sum_px += r.norm() * px_per_residual;
    }
    if (!(sum_px / (l.observations.size() - 1) <= options_.outlier_reprojection_px))
      outliers.push_back(id);
  }
  for (int64_t id : outliers) landmarks_.reject(id);
  stats_.outliers_rejected += static_cast<int>(outliers.size());
}

void SlidingWindowEstimator::removeGaugeDrift(const Eigen::Vector3d& p0_before,
                                              const Eigen::Matrix3d& R0_before) {
  // As VINS-Mono's double2vector: rotate (about world z) and shift the whole window so that the
  // oldest frame keeps its yaw and position. The yaw is taken from the relative rotation (the
  // z-rotation closest to it), not from Euler angles of the frame, which degenerate when the
  // body's x axis points up (EuRoC's IMU).
  const Eigen::Matrix3d delta = R0_before * frames_.front()->q().toRotationMatrix().transpose();
  const double yaw = std::atan2(delta(1, 0) - delta(0, 1), delta(0, 0) + delta(1, 1));
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  moveWorld(Rz, p0_before - Rz * frames_.front()->p());
}

void SlidingWindowEstimator::moveWorld(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  std::vector<const double*> poses, speed_biases;
  for (auto& f : frames_) {
    setPose(R * f->p() + t, Eigen::Quaterniond(R) * f->q(), f->pose);
    setSpeedBias(R * f->v(), f->ba(), f->bg(), f->speed_bias);
    poses.push_back(f->pose), speed_biases.push_back(f->speed_bias);
  }
  // The prior moves with the window: left where it was linearised, it would pull the window back
  // by the move in the next solve (doc/estimator.md, "Gauge").
  if (prior_) prior_ = moveWorldFrame(*prior_, R, t, poses, speed_biases);
}

bool SlidingWindowEstimator::failureDetected(const Eigen::Vector3d& predicted_p,
                                             std::string* why) const {
  for (const auto& f : frames_) {
    for (double x : f->pose)
      if (!std::isfinite(x)) return *why = "non-finite pose", true;
    for (double x : f->speed_bias)
      if (!std::isfinite(x)) return *why = "non-finite velocity or bias", true;
  }
  const Frame& n = *frames_.back();
  if (n.ba().norm() > options_.max_accel_bias) return *why = "accelerometer bias too large", true;
  if (n.bg().norm() > options_.max_gyro_bias) return *why = "gyro bias too large", true;
  if (n.v().norm() > options_.max_speed) return *why = "speed too large", true;
  if (!(std::abs(td_) < options_.max_time_offset_s))
    return *why = "time offset estimate beyond max_time_offset_s", true;
  if ((n.p() - predicted_p).norm() > options_.max_position_jump)
    return *why = "position jumped away from the IMU prediction", true;
  return false;
}

void SlidingWindowEstimator::reset(const std::string& why, bool imu_continuous) {
  ++stats_.resets;
  // What to carry through the outage: the last output state, or (a reset before the first output
  // since the previous one) the state carried so far.
  if (!imu_continuous || options_.reset_dead_reckoning_max_s <= 0) {
    dead_reckoned_.clear();
  } else if (last_output_) {
    dead_reckoned_ = {{last_output_->t_ns, *last_output_}};
  }
  last_output_.reset();
  stats_.last_failure = why;
  few_features_since_ns_ = -1;
  frames_.clear();
  landmarks_.clear();
  prior_.reset();
  initialized_ = false;
  if (!(std::abs(td_) < options_.max_time_offset_s)) td_ = options_.time_offset_s;
}

void SlidingWindowEstimator::deadReckonToNewest() {
  const EstimatorState& from = dead_reckoned_.rbegin()->second;
  const int64_t to_ns = frames_.back()->imuTimeNs();
  if (to_ns <= from.t_ns) return;
  if (data::nsToSec(to_ns - dead_reckoned_.begin()->first) > options_.reset_dead_reckoning_max_s) {
    dead_reckoned_.clear();  // too long on the IMU alone: the next initialisation starts afresh
    return;
  }
  const auto imu = preintegrate(from.t_ns, to_ns, from.accel_bias, from.gyro_bias);
  const double T = imu->sumDt();
  const Eigen::Vector3d& g = imu_options_.gravity_W;
  EstimatorState s = from;
  s.t_ns = to_ns;
  s.p_W_B = from.p_W_B + from.v_W * T + 0.5 * g * T * T + from.q_W_B * imu->deltaP();
  s.v_W = from.v_W + g * T + from.q_W_B * imu->deltaV();
  s.q_W_B = (from.q_W_B * imu->deltaQ()).normalized();
  dead_reckoned_[to_ns] = s;
}

void SlidingWindowEstimator::continueFromDeadReckoning() {
  const auto it = dead_reckoned_.find(frames_.front()->imuTimeNs());
  if (it == dead_reckoned_.end()) {
    dead_reckoned_.clear();
    return;
  }
  // Both worlds have z against gravity: a rotation about z and a shift move the new one onto the
  // old, so that the oldest window frame lands on its carried pose.
  const Frame& oldest = *frames_.front();
  const Eigen::Matrix3d R = it->second.q_W_B.toRotationMatrix() * oldest.q().toRotationMatrix().transpose();
  const Eigen::Matrix3d R_yaw = Eigen::AngleAxisd(std::atan2(R(1, 0), R(0, 0)), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  moveWorld(R_yaw, it->second.p_W_B - R_yaw * oldest.p());
  ++stats_.resets_continued;
  dead_reckoned_.clear();
}

bool SlidingWindowEstimator::secondNewestIsKeyframe() const {
  const int n = static_cast<int>(frames_.size());
  int common = 0;
  const double parallax_px = landmarks_.meanParallax(n - 3, n - 2, &common) * focal_px_;
  return frames_.back()->stationary || parallax_px >= options_.keyframe_parallax_px ||
         common < options_.keyframe_min_tracked;
}

void SlidingWindowEstimator::slideWindow() {
  if (static_cast<int>(frames_.size()) <= options_.window_size) return;
  const auto t0 = std::chrono::steady_clock::now();
  if (secondNewestIsKeyframe())
    marginalizeOldest();
  else
    dropSecondNewest();
  stats_.marginalization_ms.push_back(data::msSince(t0));
}

void SlidingWindowEstimator::setCalibrationRoles(Marginalizer* m) const {
  // Estimated: the prior keeps what it learnt. Fixed: no part of the prior.
  if (options_.estimate_extrinsic)
    m->setManifold(T_B_C_, &kPoseManifold);
  else
    m->setConstant(T_B_C_);
  if (!options_.estimate_time_offset) m->setConstant(&td_);  // else Euclidean
}

const ceres::CostFunction* SlidingWindowEstimator::reprojectionCost(const Observation& host,
                                                                   const Observation& o,
                                                                   double sqrt_info, Landmark& l,
                                                                   std::vector<double*>* blocks) {
  *blocks = {frames_[host.frame]->pose, frames_[o.frame]->pose, T_B_C_, &l.inverse_depth};
  if (!options_.estimate_time_offset) return reprojection_factors_.plain(host.point, o.point, sqrt_info);
  blocks->push_back(&td_);
  return reprojection_factors_.withTimeOffset(host.point, o.point, host.velocity, o.velocity,
                                              frames_[host.frame]->td, frames_[o.frame]->td,
                                              sqrt_info);
}

void SlidingWindowEstimator::marginalizeOldest() {
  Marginalizer m;
  for (auto& f : frames_) m.setManifold(f->pose, &kPoseManifold);
  setCalibrationRoles(&m);
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  ceres::HuberLoss huber(options_.huber_px);
  Frame& oldest = *frames_[0];
  std::vector<const double*> marginalized{oldest.pose, oldest.speed_bias};

  if (prior_) m.addPrior(prior_, options_.first_estimate_jacobians);
  if (frames_[1]->imu && frames_[1]->imu->sumDt() <= 10.0) {
    costs.push_back(std::make_unique<ImuFactor>(frames_[1]->imu));
    m.addResidualBlock(costs.back().get(), nullptr,
                       {oldest.pose, oldest.speed_bias, frames_[1]->pose, frames_[1]->speed_bias});
  }
  for (auto& cost : restFactors(oldest)) {
    costs.push_back(std::move(cost));
    m.addResidualBlock(costs.back().get(), nullptr, {oldest.speed_bias});
  }
  if (oldest.accel_bias_prior_sigma > 0) {
    costs.push_back(accelBiasPrior(oldest));
    m.addResidualBlock(costs.back().get(), nullptr, {oldest.speed_bias});
  }
  const double sqrt_info = reprojectionSqrtInformation(focal_px_, options_.pixel_sigma);
  std::vector<double*> blocks;
  reprojection_factors_.reuseAll();
  for (auto& [id, l] : landmarks_.landmarks()) {
    if (!l.has_depth || l.observations.size() < 2 || l.hostFrame() != 0) continue;
    const Observation& host = l.observations.front();
    for (size_t k = 1; k < l.observations.size(); ++k)
      m.addResidualBlock(reprojectionCost(host, l.observations[k], sqrt_info, l, &blocks), &huber,
                         blocks);
    marginalized.push_back(&l.inverse_depth);
  }
  try {
    prior_ = m.marginalize(marginalized);
  } catch (const std::invalid_argument&) {
    prior_.reset();  // nothing connected the oldest frame to the rest: no prior to keep
  }
  if (prior_) {
    std::vector<const double*> poses, speed_biases;
    for (auto& f : frames_) poses.push_back(f->pose), speed_biases.push_back(f->speed_bias);
    stats_.prior_yaw_information.push_back(informationAlongYaw(*prior_, poses, speed_biases));
  }
  const auto T_W_C = cameraPoses();
  frames_.pop_front();
  landmarks_.removeFrame(0, &T_W_C);
  frames_.front()->imu = nullptr;
  while (imu_.size() > 2 && imu_[1].t_ns <= frames_.front()->imuTimeNs()) imu_.pop_front();
  ++stats_.keyframes;
}

void SlidingWindowEstimator::dropSecondNewest() { dropFrame(static_cast<int>(frames_.size()) - 2); }

void SlidingWindowEstimator::dropFrame(int idx) {
  Frame& second = *frames_[idx];
  Frame& newest = *frames_[idx + 1];
  if (prior_ &&
      (contains(prior_->blocks, second.pose) || contains(prior_->blocks, second.speed_bias))) {
    Marginalizer m;
    for (auto& f : frames_) m.setManifold(f->pose, &kPoseManifold);
    setCalibrationRoles(&m);
    m.addPrior(prior_, options_.first_estimate_jacobians);
    std::vector<const double*> marginalized;
    if (contains(prior_->blocks, second.pose)) marginalized.push_back(second.pose);
    if (contains(prior_->blocks, second.speed_bias)) marginalized.push_back(second.speed_bias);
    try {
      prior_ = m.marginalize(marginalized);
    } catch (const std::invalid_argument&) {
      prior_.reset();
    }
  }
  // One preintegration from the frame before `second` to the newest.
  const Frame& before = *frames_[idx - 1];
  auto merged = std::make_shared<ImuPreintegration>(second.imu->samples().front(), before.ba(),
                                                    before.bg(), imu_options_);
  for (size_t k = 1; k < second.imu->samples().size(); ++k)
    merged->integrate(second.imu->samples()[k]);
  for (size_t k = 1; k < newest.imu->samples().size(); ++k)
    merged->integrate(newest.imu->samples()[k]);
  newest.imu = merged;
  const auto T_W_C = cameraPoses();
  frames_.erase(frames_.begin() + idx);
  landmarks_.removeFrame(idx, &T_W_C);
}

}  // namespace adugs::vio
