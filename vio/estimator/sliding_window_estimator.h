#pragma once
// The monocular visual-inertial estimator of doc/architecture.md "The method" (VINS-Mono's
// back-end): a sliding window of frames with IMU preintegration between consecutive ones, landmarks
// as inverse depths in their host frame, Ceres cost functions for reprojection (robust), IMU and
// marginalisation prior factors solved by the project's own Levenberg-Marquardt
// (vio/estimator/window_solver.h), and marginalisation of the oldest frame (when the second-newest
// is a keyframe by parallax) or dropping of the second-newest (when it adds nothing).
//
// Per frame: preintegrate the IMU since the previous frame, predict the new state, add the
// features. Not initialised: try the static initialiser (quiet IMU, no image motion), then the
// visual-inertial one on a full window. Initialised: triangulate new landmarks, solve, check for
// failure (non-finite, huge bias/speed, jump, too few features) -> reset, else slide the window.
//
// Body = IMU frame, T_W_B, gravity (0, 0, -9.81) in W. Camera-IMU time offset td (Kalibr's
// convention, t_imu = t_cam + td): a frame stamped t_cam is the state at IMU time t_cam + td,
// with td the calibrated value or, with estimate_time_offset, the estimate when the frame came in
// (VINS-Mono's scheme: later changes of td move each observation along its image velocity).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "data/types.h"
#include "vio/estimator/estimator_options.h"
#include "vio/estimator/landmark_map.h"
#include "vio/estimator/marginalization.h"
#include "vio/estimator/relative_pose_estimate.h"
#include "vio/estimator/reprojection_factor_pool.h"
#include "vio/frontend/frame_features.h"
#include "vio/imu/imu_preintegration.h"

namespace ceres {
class CostFunction;
}

namespace adugs::vio {

class WindowSolver;

struct EstimatorState {
  int64_t t_ns = 0;  // IMU clock: the frame's camera stamp + the time offset it was added with
  Eigen::Vector3d p_W_B = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_W_B = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  bool stationary = false;
};

struct EstimatorStats {
  int frames = 0;
  int keyframes = 0;  // frames that left the window by marginalisation (oldest)
  int resets = 0;
  int resets_continued = 0;  // of which the re-initialised window continued the trajectory
  int64_t init_t_ns = -1;    // time of the (first) initialisation
  std::string init_kind;     // "static" or "visual-inertial"
  std::string last_failure;  // why the last reset happened
  std::string last_init_failure;
  double init_scale_relative_std = -1;  // of the first visual-inertial initialisation; -1 none
  int init_refused_uncertain_scale = 0;  // windows refused by InitOptions::max_scale_relative_std
  int landmarks_in_last_solve = 0;
  int frames_without_imu = 0;  // skipped: no IMU sample within max_imu_gap_s of the frame
  int outliers_rejected = 0;   // landmarks removed for their reprojection error
  int64_t solver_iterations = 0;  // window-solver steps tried, summed over the solves
  int64_t solver_successful = 0;  // of which accepted
  int solves = 0;
  int solves_cut_by_time = 0;     // solves stopped by max_solver_time_s before max_iterations
  std::vector<double> solve_ms, marginalization_ms;  // per solved frame
  // After each marginalisation of the oldest frame: the information its prior holds along the
  // window's unobservable turn about gravity (marginalization.h, informationAlongYaw) [rad^-2].
  std::vector<double> prior_yaw_information;
  // With EstimatorOptions::report_relative_covariance: per solve, the newest frame relative to the
  // oldest with the window's covariance of it.
  std::vector<RelativePoseEstimate> relative_poses;
};

class SlidingWindowEstimator {
 public:
  // T_B_C: camera -> body. focal_px converts pixel thresholds to normalised units.
  SlidingWindowEstimator(const EstimatorOptions& options, double focal_px,
                         const Eigen::Isometry3d& T_B_C,
                         const ImuPreintegrationOptions& imu_options);

  // Samples must come in increasing time; a non-increasing or non-finite one throws
  // std::invalid_argument (the reader already rejects them with file/line).
  void addImu(const data::ImuSample& sample);
  // The frame's features (tracker output). Returns the state at the frame once initialised; never
  // a non-finite state. Frames before the first IMU sample are ignored (nullopt).
  std::optional<EstimatorState> addFrame(const FrameFeatures& features);

  // Gyro-integrated rotation of the body since the last frame, R_Bprev_Bnow (for the tracker's
  // KLT prediction); identity before the first frame.
  Eigen::Quaterniond rotationSinceLastFrame(int64_t t_ns) const;
  // Gyro bias of the newest frame (zero before the first frame): what a front-end running on
  // another thread integrates its own gyro prediction with.
  Eigen::Vector3d gyroBias() const;
  // Camera -> body extrinsic in use: the calibration, or its online estimate
  // (EstimatorOptions::estimate_extrinsic).
  const Eigen::Isometry3d& extrinsic() const { return T_B_C_iso_; }
  // Camera-IMU time offset td in use [s]: the calibration, or its online estimate
  // (EstimatorOptions::estimate_time_offset).
  double timeOffset() const { return td_; }

  bool initialized() const { return initialized_; }
  const EstimatorStats& stats() const { return stats_; }
  const EstimatorOptions& options() const { return options_; }  // as in effect (focal set, ...)
  // The IMU noise the preintegrations assume (accel_noise_inflation applied).
  const ImuPreintegrationOptions& imuOptions() const { return imu_options_; }
  int windowFrames() const { return static_cast<int>(frames_.size()); }

 private:
  struct Frame {
    int64_t t_ns = 0;                        // camera stamp
    double td = 0;                           // time offset when added: state at t_ns + td
    double pose[7];                          // p, q (x y z w)
    double speed_bias[9];                    // v, ba, bg
    std::shared_ptr<ImuPreintegration> imu;  // from the previous window frame (null for the first)
    FrameFeatures features;                  // kept for the visual-inertial initialisation
    bool stationary = false;
    bool has_gyro_at_rest = false;       // stationary, with the gyro mean over its IMU interval:
    Eigen::Vector3d gyro_at_rest_mean;   // the bias it measured (bias_prior_factor.h)
    Eigen::Vector3d gyro_at_rest_sigma;
    // The initialisation's first frame: its accelerometer bias held at accel_bias_prior with this
    // sigma (m/s^2; 0 = no prior; bias_prior_factor.h).
    double accel_bias_prior_sigma = 0;
    Eigen::Vector3d accel_bias_prior;
    int64_t imuTimeNs() const { return t_ns + data::secToNs(td); }
    Eigen::Vector3d p() const { return Eigen::Vector3d(pose[0], pose[1], pose[2]); }
    Eigen::Quaterniond q() const { return Eigen::Quaterniond(pose[6], pose[3], pose[4], pose[5]); }
    Eigen::Vector3d v() const {
      return Eigen::Vector3d(speed_bias[0], speed_bias[1], speed_bias[2]);
    }
    Eigen::Vector3d ba() const {
      return Eigen::Vector3d(speed_bias[3], speed_bias[4], speed_bias[5]);
    }
    Eigen::Vector3d bg() const {
      return Eigen::Vector3d(speed_bias[6], speed_bias[7], speed_bias[8]);
    }
  };

  std::shared_ptr<ImuPreintegration> preintegrate(int64_t from_ns, int64_t to_ns,
                                                  const Eigen::Vector3d& ba,
                                                  const Eigen::Vector3d& bg) const;
  data::ImuSample imuAt(int64_t t_ns) const;
  bool isStationary() const;
  // For a stationary newest frame: its gyro mean over the IMU interval since the previous frame.
  void measureGyroAtRest();
  // Longest spacing of the IMU samples covering [from_ns, to_ns], ends included.
  int64_t longestImuGap(int64_t from_ns, int64_t to_ns) const;
  bool tryInitialize();
  void solve();
  // The newest frame relative to the oldest, with the covariance of the solver's linearised
  // window given the oldest pose (EstimatorOptions::report_relative_covariance).
  void recordRelativeCovariance(WindowSolver& solver);
  // The factors standing still puts on a frame's speed-bias block: zero velocity and, when
  // measured, the gyro bias at rest (built alike for the solve and the marginalisation).
  std::vector<std::unique_ptr<ceres::CostFunction>> restFactors(const Frame& f) const;
  std::unique_ptr<ceres::CostFunction> accelBiasPrior(const Frame& f) const;
  // Holds the oldest frame's accelerometer bias at `bias` with `sigma` (0: no prior).
  void holdInitialAccelBias(const Eigen::Vector3d& bias, double sigma);
  // Removes landmarks whose mean reprojection error exceeds options_.outlier_reprojection_px.
  void rejectOutliers();
  void removeGaugeDrift(const Eigen::Vector3d& p0_before, const Eigen::Matrix3d& R0_before);
  // Moves every window frame to a new world frame, p -> R p + t, q -> R q, v -> R v (R about
  // gravity), and the marginalisation prior with them.
  void moveWorld(const Eigen::Matrix3d& R, const Eigen::Vector3d& t);
  bool failureDetected(const Eigen::Vector3d& predicted_p, std::string* why) const;
  // imu_continuous: the IMU stream has no hole, so the last state can be carried through.
  void reset(const std::string& why, bool imu_continuous = true);
  bool secondNewestIsKeyframe() const;
  void slideWindow();
  void marginalizeOldest();
  // T_B_C and td in a marginalisation: kept in the prior when estimated, else constant.
  void setCalibrationRoles(Marginalizer* m) const;
  void dropSecondNewest();
  void dropFrame(int index);  // merges its IMU into the next frame's preintegration
  void thinWindow();
  // The reprojection factor of observation o of landmark l (hosted at `host`), with or without
  // the time offset, and its parameter blocks. From reprojection_factors_: valid until its next
  // reuseAll().
  const ceres::CostFunction* reprojectionCost(const Observation& host, const Observation& o,
                                              double sqrt_info, Landmark& l,
                                              std::vector<double*>* blocks);
  std::vector<Eigen::Isometry3d> cameraPoses() const;
  // The features with the image velocities the time-offset factors use (see the .cpp); only
  // called when td is estimated.
  FrameFeatures timeOffsetVelocities(const FrameFeatures& features);
  EstimatorState stateOf(const Frame& f) const;
  void dropOldestUninitialized();
  // After a reset: carries the last output state by the IMU to the newest frame, and places a
  // fresh initialisation where the carried state is (reset_dead_reckoning_max_s).
  void deadReckonToNewest();
  void continueFromDeadReckoning();

  EstimatorOptions options_;
  double focal_px_;
  double T_B_C_[7];
  Eigen::Isometry3d T_B_C_iso_;
  Eigen::Isometry3d T_B_C_calibrated_;
  double td_ = 0;  // the one-value Ceres block of the time offset
  std::unordered_map<int64_t, Eigen::Vector2d> last_velocities_;  // feature id -> at the last frame
  ImuPreintegrationOptions imu_options_;
  std::deque<data::ImuSample> imu_;  // recent samples (kept back to the oldest window frame)
  std::deque<std::unique_ptr<Frame>> frames_;
  LandmarkMap landmarks_;
  ReprojectionFactorPool reprojection_factors_;
  std::shared_ptr<const MarginalizationPrior> prior_;
  bool initialized_ = false;
  // Camera stamp of the latest (re-)initialisation or stationary frame: td is held until the
  // estimator has been moving for time_offset_warmup_s after it.
  int64_t settled_since_ns_ = 0;
  int64_t few_features_since_ns_ = -1;  // the first of the latest run of frames with too few features (-1: none)
  EstimatorStats stats_;
  std::optional<EstimatorState> last_output_;
  // Since a reset: the last output state carried by the IMU to each frame added since, by the
  // frame's IMU time (empty when there is nothing to carry).
  std::map<int64_t, EstimatorState> dead_reckoned_;
};

}  // namespace adugs::vio
