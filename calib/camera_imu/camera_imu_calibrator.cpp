#include "calib/camera_imu/camera_imu_calibrator.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>

#include "calib/camera_imu/camera_imu_costs.h"
#include "calib/camera_imu/camera_imu_init.h"
#include "calib/solver_outcome.h"
#include "calib/text_format.h"
#include "data/formats/yaml_options.h"
#include "data/input_error.h"

namespace adugs::calib {
namespace {

using data::InputError;
using Quat = std::array<double, 4>;  // w x y z (ceres order)
using Vec3 = std::array<double, 3>;

// All the unknowns, in plain arrays Ceres can point at.
struct State {
  double t0 = 0, dt = 0;  // first knot [s, IMU clock], knot spacing
  std::vector<Quat> q;    // control rotations R_T_I
  std::vector<Vec3> p;    // control positions p_T_I
  Quat q_C_I{1, 0, 0, 0};
  Vec3 p_C_I{0, 0, 0};
  double shift = 0;
  Vec3 gravity_dir{0, 0, -1};
  // Biases: piecewise linear, knots every bias_dt from t0 (at least two).
  double bias_dt = 0;
  std::vector<Vec3> gyro_bias, accel_bias;
  int segments() const { return static_cast<int>(q.size()) - 3; }
};

struct BiasLocation {
  int k;
  double w;
};

BiasLocation biasAt(const State& s, double t) {
  const int last = static_cast<int>(s.gyro_bias.size()) - 2;
  const int k = std::clamp(static_cast<int>(std::floor((t - s.t0) / s.bias_dt)), 0, last);
  return {k, std::clamp((t - s.t0 - k * s.bias_dt) / s.bias_dt, 0.0, 1.0)};
}

Quat toQuat(const Eigen::Quaterniond& e) { return {e.w(), e.x(), e.y(), e.z()}; }
Eigen::Quaterniond fromQuat(const Quat& q) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]); }

// Camera pose at camera time t by interpolating the PnP poses (clamped at the ends).
void interpolatePose(const std::vector<BoardPose>& poses, double t, Eigen::Quaterniond& q,
                     Eigen::Vector3d& p) {
  auto it = std::lower_bound(poses.begin(), poses.end(), t,
                             [](const BoardPose& b, double x) { return b.t < x; });
  if (it == poses.begin()) {
    q = it->q_T_C, p = it->p_T_C;
    return;
  }
  if (it == poses.end()) {
    q = poses.back().q_T_C, p = poses.back().p_T_C;
    return;
  }
  const BoardPose& a = *(it - 1);
  const double s = (t - a.t) / (it->t - a.t);
  q = a.q_T_C.slerp(s, it->q_T_C);
  p = (1 - s) * a.p_T_C + s * it->p_T_C;
}

struct Segment {
  int index;
  double u;
};

// Segment of a time, clamped to the spline (u may then leave [0, 1) slightly: the segment's
// polynomial extrapolates smoothly, which only happens at the very ends).
Segment segmentOf(const State& s, double t) {
  const SplineLocation loc = locateOnSpline(t, s.t0, s.dt);
  const int i = std::clamp(loc.segment, 0, s.segments() - 1);
  return {i, (t - s.t0 - i * s.dt) / s.dt};
}

struct FrameData {
  double t_cam;  // camera clock [s]
  std::vector<FrameReprojection::Corner> corners;
};

void addSplineBlocks(State& s, int seg, std::vector<double*>& blocks, bool with_positions) {
  for (int j = 0; j < 4; ++j) blocks.push_back(s.q[seg + j].data());
  if (with_positions)
    for (int j = 0; j < 4; ++j) blocks.push_back(s.p[seg + j].data());
}

// kSpline fits the trajectory, biases and gravity with T_C_I and the shift held at their initial
// guess: the spline starts from PnP poses too noisy to differentiate twice, and freeing the
// extrinsics against those accelerations lets them run away. kFull then frees everything.
// The problem is rebuilt on every call: frame segments follow the time shift, weights change.
enum class Stage { kSpline, kFull };

// covariance: after the solve, the 1-sigma of T_C_I and the shift into res (the final solve).
void solve(State& s, const std::vector<FrameData>& frames, const ImuRecording& imu,
           const std::vector<size_t>& imu_used, Stage stage, const CalibCamera& camera,
           const ImuNoiseFigures& noise, const CameraImuOptions& o, CameraImuResult& res,
           bool covariance = false) {
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  ceres::QuaternionManifold quaternion;
  ceres::SphereManifold<3> sphere;
  const double inv_dt = 1.0 / s.dt;

  for (const FrameData& f : frames) {
    const Segment sg = segmentOf(s, f.t_cam + s.shift);
    auto* functor = new FrameReprojection{f.t_cam - (s.t0 + sg.index * s.dt), inv_dt, &camera,
                                          f.corners, 1.0 / o.pixel_sigma};
    auto* cost =
        new ceres::AutoDiffCostFunction<FrameReprojection, ceres::DYNAMIC, 4, 4, 4, 4, 3, 3, 3, 3,
                                        4, 3, 1>(functor, 2 * static_cast<int>(f.corners.size()));
    std::vector<double*> blocks;
    addSplineBlocks(s, sg.index, blocks, true);
    blocks.push_back(s.q_C_I.data());
    blocks.push_back(s.p_C_I.data());
    blocks.push_back(&s.shift);
    problem.AddResidualBlock(cost, nullptr, blocks);
  }
  const double rate = noise.update_rate_hz > 0 ? noise.update_rate_hz : imu.rate_hz;
  const double inv_sigma_g = 1.0 / (noise.gyro_noise_density * std::sqrt(rate));
  const double inv_sigma_a = 1.0 / (noise.accel_noise_density * std::sqrt(rate));
  for (size_t k : imu_used) {
    const double t = static_cast<double>(imu.t_ns[k] - imu.t_ns.front()) * 1e-9;
    const Segment sg = segmentOf(s, t);
    const BiasLocation bl = biasAt(s, t);
    auto* gyro = new ceres::AutoDiffCostFunction<GyroResidual, 3, 4, 4, 4, 4, 3, 3>(
        new GyroResidual{sg.u, inv_dt, imu.gyro[k], inv_sigma_g, bl.w});
    std::vector<double*> gb;
    addSplineBlocks(s, sg.index, gb, false);
    gb.push_back(s.gyro_bias[bl.k].data());
    gb.push_back(s.gyro_bias[bl.k + 1].data());
    problem.AddResidualBlock(gyro, nullptr, gb);
    auto* acc = new ceres::AutoDiffCostFunction<AccelResidual, 3, 4, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3>(
        new AccelResidual{sg.u, inv_dt, imu.accel[k], inv_sigma_a, o.gravity, bl.w});
    std::vector<double*> ab;
    addSplineBlocks(s, sg.index, ab, true);
    ab.push_back(s.accel_bias[bl.k].data());
    ab.push_back(s.accel_bias[bl.k + 1].data());
    ab.push_back(s.gravity_dir.data());
    problem.AddResidualBlock(acc, nullptr, ab);
  }
  // Random-walk priors tie consecutive bias knots (continuous random walk over bias_dt).
  for (size_t k = 0; k + 1 < s.gyro_bias.size(); ++k) {
    const double walk = std::sqrt(s.bias_dt);
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<BiasWalkResidual, 3, 3, 3>(
            new BiasWalkResidual{1.0 / (std::max(noise.gyro_random_walk, 1e-7) * walk)}),
        nullptr, s.gyro_bias[k].data(), s.gyro_bias[k + 1].data());
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<BiasWalkResidual, 3, 3, 3>(
            new BiasWalkResidual{1.0 / (std::max(noise.accel_random_walk, 1e-6) * walk)}),
        nullptr, s.accel_bias[k].data(), s.accel_bias[k + 1].data());
  }
  for (auto& q : s.q)
    if (problem.HasParameterBlock(q.data())) problem.SetManifold(q.data(), &quaternion);
  problem.SetManifold(s.q_C_I.data(), &quaternion);
  if (stage == Stage::kSpline) {
    problem.SetParameterBlockConstant(s.q_C_I.data());
    problem.SetParameterBlockConstant(s.p_C_I.data());
    problem.SetParameterBlockConstant(&s.shift);
  } else if (!o.estimate_time_offset) {
    problem.SetParameterBlockConstant(&s.shift);
  }
  problem.SetManifold(s.gravity_dir.data(), &sphere);

  ceres::Solver::Options so = quietSolverOptions();
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.max_num_iterations = o.max_iterations;
  so.num_threads = o.threads;
  so.minimizer_progress_to_stdout = o.verbose;
  so.function_tolerance = 1e-9;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  res.iterations += static_cast<int>(summary.iterations.size());
  const SolverOutcome outcome = describeSolve(summary);
  res.final_solve_usable = outcome.usable;
  res.final_solve_converged = outcome.converged;
  if (!outcome.usable) {
    res.solver_failures.push_back((stage == Stage::kSpline ? "trajectory solve: " : "full solve: ") +
                                  outcome.problem);
  }
  if (o.verbose) std::cerr << summary.BriefReport() << "\n";
  if (!covariance || !outcome.usable) return;

  // Marginal covariance of the extrinsics and the shift in the whole problem (spline, biases and
  // gravity marginalised), from the residuals' own noise model (corners pixel_sigma, IMU white
  // noise): no rescaling by the residual variance, whose types differ.
  const auto t0 = std::chrono::steady_clock::now();
  ceres::Covariance::Options co;
  co.num_threads = o.threads;
  co.apply_loss_function = true;
  ceres::Covariance cov(co);
  std::vector<std::pair<const double*, const double*>> blocks = {
      {s.q_C_I.data(), s.q_C_I.data()}, {s.p_C_I.data(), s.p_C_I.data()}};
  const bool with_shift = o.estimate_time_offset;
  if (with_shift) blocks.push_back({&s.shift, &s.shift});
  if (cov.Compute(blocks, &problem)) {
    Eigen::Matrix3d Cq, Cp;
    double Cs = 0;
    cov.GetCovarianceBlockInTangentSpace(s.q_C_I.data(), s.q_C_I.data(), Cq.data());
    cov.GetCovarianceBlock(s.p_C_I.data(), s.p_C_I.data(), Cp.data());
    if (with_shift) cov.GetCovarianceBlock(&s.shift, &s.shift, &Cs);
    // Ceres's quaternion tangent is half the rotation angle.
    res.sigma_rotation = 2 * Cq.diagonal().cwiseMax(0).cwiseSqrt();
    // Camera position in the IMU frame, p_I_C = -R_C_I^T p_C_I (the lever arm's rotation part is
    // negligible next to Cp at these sizes).
    const Eigen::Matrix3d R = fromQuat(s.q_C_I).normalized().toRotationMatrix();
    res.sigma_translation = (R.transpose() * Cp * R).diagonal().cwiseMax(0).cwiseSqrt();
    res.sigma_time_shift_s = std::sqrt(std::max(0.0, Cs));
    res.has_sigma = res.sigma_rotation.allFinite() && res.sigma_translation.allFinite();
  }
  res.covariance_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Gravity direction in the target frame: g = a_T - R_T_I f, averaged over the IMU samples.
void initGravity(State& s, const std::vector<RateSample>& gyro, const ImuRecording& imu,
                 const std::vector<size_t>& imu_used) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (size_t k : imu_used) {
    const Segment sg = segmentOf(s, gyro[k].t);
    const int i = sg.index;
    const double* q[4] = {s.q[i].data(), s.q[i + 1].data(), s.q[i + 2].data(), s.q[i + 3].data()};
    const double* p[4] = {s.p[i].data(), s.p[i + 1].data(), s.p[i + 2].data(), s.p[i + 3].data()};
    double q_T_I[4], pos[3], acc[3];
    evalRotationSpline(q, sg.u, 1.0 / s.dt, q_T_I, static_cast<double*>(nullptr));
    evalPositionSpline(p, sg.u, 1.0 / s.dt, pos, static_cast<double*>(nullptr), acc);
    sum += Eigen::Vector3d(acc[0], acc[1], acc[2]) -
           fromQuat({q_T_I[0], q_T_I[1], q_T_I[2], q_T_I[3]}) * imu.accel[k];
  }
  const Eigen::Vector3d g = sum.normalized();
  s.gravity_dir = {g.x(), g.y(), g.z()};
}

// Per-corner errors of all frames at the current state (pixels, unweighted); NaN for a corner
// behind the camera (it has no reprojection error).
std::vector<std::vector<double>> cornerErrors(const State& s, const std::vector<FrameData>& frames,
                                              const CalibCamera& camera) {
  std::vector<std::vector<double>> errors;
  std::vector<bool> behind;
  for (const FrameData& f : frames) {
    const Segment sg = segmentOf(s, f.t_cam + s.shift);
    FrameReprojection fr{f.t_cam - (s.t0 + sg.index * s.dt), 1.0 / s.dt, &camera, f.corners, 1.0};
    for (auto& c : fr.corners) c.weight = 1;
    std::vector<double> r(2 * fr.corners.size());
    const int i = sg.index;
    fr.project(s.q[i].data(), s.q[i + 1].data(), s.q[i + 2].data(), s.q[i + 3].data(),
               s.p[i].data(), s.p[i + 1].data(), s.p[i + 2].data(), s.p[i + 3].data(),
               s.q_C_I.data(), s.p_C_I.data(), &s.shift, r.data(), &behind);
    std::vector<double> e(fr.corners.size());
    for (size_t k = 0; k < e.size(); ++k)
      e[k] = behind[k] ? std::numeric_limits<double>::quiet_NaN()
                       : std::hypot(r[2 * k], r[2 * k + 1]);
    errors.push_back(std::move(e));
  }
  return errors;
}

double rms(const std::vector<TimedVector>& v) {
  double sq = 0;
  for (const auto& x : v) sq += x.v.squaredNorm();
  return v.empty() ? 0 : std::sqrt(sq / (3.0 * v.size()));
}

}  // namespace

void readCameraImuOptions(data::YamlOptionsReader& r, CameraImuOptions& o) {
  r.optional("knot_rate_hz", o.knot_rate_hz, 1.0, 200.0);
  r.optional("estimate_time_offset", o.estimate_time_offset);
  r.optional("max_time_offset_s", o.max_time_offset_s, 0.0, 10.0);
  r.optional("bias_knot_interval_s", o.bias_knot_interval_s, 0.0, 1e6);
  r.optional("frame_step", o.frame_step, 1, 1000000);
  r.optional("min_corners", o.min_corners, 4, 100000);
  r.optional("min_frames", o.min_frames, 2, 1000000);
  r.optional("pixel_sigma", o.pixel_sigma, 1e-3, 1e3);
  r.optional("huber_px", o.huber_px, 1e-3, 1e3);
  r.optional("robust_rounds", o.robust_rounds, 1, 100);
  r.optional("max_iterations", o.max_iterations, 1, 100000);
  r.optional("min_rotation_rate", o.min_rotation_rate, 0.0, 100.0);
  r.optional("compute_covariance", o.compute_covariance);
}

CameraImuResult calibrateCameraImu(const std::vector<TargetObservation>& views,
                                   const CalibCamera& camera, const ImuRecording& imu,
                                   const ImuNoiseFigures& noise, const CameraImuOptions& o,
                                   const CameraImuSources& src) {
  const auto start = std::chrono::steady_clock::now();
  CameraImuResult res;
  res.views_given = static_cast<int>(views.size());
  if (imu.t_ns.size() < 100)
    throw InputError(src.imu, 0, "", strprintf("only %zu IMU samples", imu.t_ns.size()));
  if (!(noise.gyro_noise_density > 0 && noise.accel_noise_density > 0))
    throw InputError(src.imu, 0, "noise",
                     "gyro and accelerometer noise densities must be positive");
  const int64_t origin = imu.t_ns.front();
  const double imu_end = static_cast<double>(imu.t_ns.back() - origin) * 1e-9;

  // Corners outside the image of the intrinsics: the files describe different cameras.
  size_t corners = 0, off_image = 0;
  for (const auto& v : views)
    for (const auto& c : v.corners) {
      ++corners;
      off_image += !(c.pixel.x() >= -0.5 && c.pixel.y() >= -0.5 &&
                     c.pixel.x() < camera.width - 0.5 && c.pixel.y() < camera.height - 0.5);
    }
  if (off_image > corners / 100)
    throw InputError(
        src.corners, 0, "kp_x",
        strprintf("%zu of %zu corners lie outside the %dx%d image of the intrinsics "
                  "in %s: detections and intrinsics are of different cameras?",
                  off_image, corners, camera.width, camera.height, src.intrinsics.c_str()));

  // Frames with enough corners, every frame_step-th, inside the IMU time span.
  std::vector<TargetObservation> usable;
  int outside = 0, with_target = 0;
  for (size_t v = 0; v < views.size(); v += std::max(1, o.frame_step)) {
    if (static_cast<int>(views[v].corners.size()) < o.min_corners) continue;
    ++with_target;
    const double t = static_cast<double>(views[v].t_ns - origin) * 1e-9;
    if (t < 0.05 || t > imu_end - 0.05) {
      ++outside;
      continue;
    }
    usable.push_back(views[v]);
  }
  // No frame inside the IMU's span: files of different recordings or clocks (input error). Some
  // outside: calibrated on the covered frames; the verdict says how many were dropped.
  res.frames_with_target = with_target;
  res.frames_outside_imu = outside;
  if (with_target > 0 && outside == with_target)
    throw InputError(src.imu, 0, "timestamps",
                     strprintf("the IMU does not cover the images: all %d frames with the "
                               "target lie outside the IMU time span [%lld, %lld] ns",
                               with_target, static_cast<long long>(origin),
                               static_cast<long long>(imu.t_ns.back())));

  const std::vector<BoardPose> poses = estimateBoardPoses(usable, camera, origin, o.min_corners);
  if (static_cast<int>(poses.size()) < o.min_frames)
    throw InputError(src.corners, 0, "",
                     strprintf("too few usable frames: %zu with a board pose (>= %d corners and a "
                               "consistent PnP) out of %zu views, need at least %d",
                               poses.size(), o.min_corners, views.size(), o.min_frames));
  double pnp_sq = 0;
  for (const auto& p : poses) pnp_sq += p.rms_px * p.rms_px;
  res.pnp_rms_px = std::sqrt(pnp_sq / poses.size());

  // Gyro samples as rate series; excitation check over the frames' span.
  std::vector<RateSample> gyro;
  gyro.reserve(imu.t_ns.size());
  for (size_t k = 0; k < imu.t_ns.size(); ++k)
    gyro.push_back({static_cast<double>(imu.t_ns[k] - origin) * 1e-9, imu.gyro[k]});
  {
    std::vector<RateSample> span;
    for (const auto& g : gyro)
      if (g.t >= poses.front().t && g.t <= poses.back().t) span.push_back(g);
    res.excitation = rotationExcitation(span);
  }
  res.duration_s = poses.back().t - poses.front().t;
  // Without rotation there is nothing to align the gyro with: not solved (the verdict fails it).
  if (res.excitation(0) < o.min_rotation_rate) {
    res.solved = false;
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return res;
  }

  // Initial guess: time offset by correlation, then R_C_I by Kabsch.
  std::vector<double> gaps;
  for (size_t k = 1; k < poses.size(); ++k) gaps.push_back(poses[k].t - poses[k - 1].t);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  const double frame_dt = gaps[gaps.size() / 2];
  const std::vector<RateSample> cam_rates = cameraAngularRates(poses, 1.5 * frame_dt);
  res.time_shift_init_s =
      o.estimate_time_offset
          ? timeOffsetByCorrelation(cam_rates, gyro, frame_dt, o.max_time_offset_s)
          : 0;
  res.R_C_I_init = rotationFromAngularRates(cam_rates, gyro, frame_dt, res.time_shift_init_s,
                                            &res.init_rate_rms);

  // Spline over the frames' span (IMU clock) with a margin for the shift to move.
  State s;
  s.dt = 1.0 / o.knot_rate_hz;
  s.shift = res.time_shift_init_s;
  s.q_C_I = toQuat(Eigen::Quaterniond(res.R_C_I_init));
  const double margin = 0.5 * s.dt;
  s.t0 = std::max(poses.front().t + s.shift - margin, gyro.front().t);
  const double t_end = std::min(poses.back().t + s.shift + margin, gyro.back().t);
  const int segments = static_cast<int>(std::ceil((t_end - s.t0) / s.dt));
  const Eigen::Quaterniond q_I_C(res.R_C_I_init.transpose());
  for (int j = 0; j < segments + 3; ++j) {
    Eigen::Quaterniond q_T_C;
    Eigen::Vector3d p_T_C;
    interpolatePose(poses, s.t0 + (j - 1) * s.dt - s.shift, q_T_C, p_T_C);
    s.q.push_back(toQuat((q_T_C * q_I_C).normalized()));
    s.p.push_back({p_T_C.x(), p_T_C.y(), p_T_C.z()});
  }
  res.control_points = static_cast<int>(s.q.size());
  const double span = segments * s.dt;
  const int bias_knots =
      o.bias_knot_interval_s > 0
          ? std::max(2, static_cast<int>(std::ceil(span / o.bias_knot_interval_s)) + 1)
          : 2;
  s.bias_dt = span / (bias_knots - 1);
  s.gyro_bias.assign(bias_knots, Vec3{0, 0, 0});
  s.accel_bias.assign(bias_knots, Vec3{0, 0, 0});

  std::vector<FrameData> frames;
  for (const auto& p : poses) {
    FrameData f{p.t, {}};
    for (const auto& c : usable[p.view].corners) f.corners.push_back({c.point, c.pixel, 1.0});
    frames.push_back(std::move(f));
  }
  res.frames_used = static_cast<int>(frames.size());
  for (const FrameData& f : frames) res.corners_in_frames += static_cast<int>(f.corners.size());

  // IMU samples on the spline.
  std::vector<size_t> imu_used;
  for (size_t k = 0; k < gyro.size(); ++k)
    if (gyro[k].t >= s.t0 && gyro[k].t < s.t0 + segments * s.dt) imu_used.push_back(k);
  res.imu_samples_used = static_cast<int>(imu_used.size());

  initGravity(s, gyro, imu, imu_used);
  solve(s, frames, imu, imu_used, Stage::kSpline, camera, noise, o, res);

  // Robust rounds: solve, then Huber IRLS weights w = min(1, sqrt(k / e)) on each corner.
  for (int round = 0; round < std::max(1, o.robust_rounds); ++round) {
    if (round > 0) {
      const auto errors = cornerErrors(s, frames, camera);
      for (size_t f = 0; f < frames.size(); ++f)
        for (size_t k = 0; k < frames[f].corners.size(); ++k) {
          const double e = errors[f][k];  // NaN (behind the camera) cannot happen here: the
                                          // solver rejects steps that put a corner there
          frames[f].corners[k].weight = e > o.huber_px ? std::sqrt(o.huber_px / e) : 1.0;
        }
    }
    const bool last = round + 1 == std::max(1, o.robust_rounds);
    solve(s, frames, imu, imu_used, Stage::kFull, camera, noise, o, res,
          last && o.compute_covariance);
  }

  // Results and residuals.
  const Eigen::Quaterniond q_C_I = fromQuat(s.q_C_I).normalized();
  res.T_C_I.linear() = q_C_I.toRotationMatrix();
  res.T_C_I.translation() = Eigen::Vector3d(s.p_C_I[0], s.p_C_I[1], s.p_C_I[2]);
  res.time_shift_s = s.shift;
  res.gravity_T = o.gravity * Eigen::Vector3d(s.gravity_dir[0], s.gravity_dir[1], s.gravity_dir[2]);
  for (size_t k = 0; k < s.gyro_bias.size(); ++k) {
    const Eigen::Vector3d g(s.gyro_bias[k].data()), a(s.accel_bias[k].data());
    res.gyro_bias += g / static_cast<double>(s.gyro_bias.size());
    res.accel_bias += a / static_cast<double>(s.accel_bias.size());
    res.bias_knots.push_back({s.t0 + k * s.bias_dt, g, a});
  }
  // Reprojection statistics over the corners that project (a corner behind the camera has no
  // error to average; it is counted instead).
  double sq = 0;
  for (const auto& frame_errors : cornerErrors(s, frames, camera))
    for (double e : frame_errors) {
      if (!std::isfinite(e)) {
        ++res.corners_behind_camera;
        continue;
      }
      res.corner_errors_px.push_back(e);
      sq += e * e;
      res.corners_downweighted += e > o.huber_px;
    }
  res.corners_used = static_cast<int>(res.corner_errors_px.size());
  res.reprojection_rms_px = res.corners_used > 0
                                ? std::sqrt(sq / res.corners_used)
                                : std::numeric_limits<double>::quiet_NaN();
  for (size_t k : imu_used) {
    const Segment sg = segmentOf(s, gyro[k].t);
    const BiasLocation bl = biasAt(s, gyro[k].t);
    const int i = sg.index;
    Eigen::Vector3d rg, ra;
    GyroResidual{sg.u, 1.0 / s.dt, imu.gyro[k], 1.0, bl.w}(
        s.q[i].data(), s.q[i + 1].data(), s.q[i + 2].data(), s.q[i + 3].data(),
        s.gyro_bias[bl.k].data(), s.gyro_bias[bl.k + 1].data(), rg.data());
    AccelResidual{sg.u, 1.0 / s.dt, imu.accel[k], 1.0, o.gravity, bl.w}(
        s.q[i].data(), s.q[i + 1].data(), s.q[i + 2].data(), s.q[i + 3].data(), s.p[i].data(),
        s.p[i + 1].data(), s.p[i + 2].data(), s.p[i + 3].data(), s.accel_bias[bl.k].data(),
        s.accel_bias[bl.k + 1].data(), s.gravity_dir.data(), ra.data());
    res.gyro_residuals.push_back({gyro[k].t, rg});
    res.accel_residuals.push_back({gyro[k].t, ra});
  }
  res.gyro_rms = rms(res.gyro_residuals);
  res.accel_rms = rms(res.accel_residuals);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

}  // namespace adugs::calib
