#pragma once
// Smooth body (IMU) trajectories for the simulator, with exact derivatives so that the synthetic
// IMU is the true derivative of the ground truth (no finite differences).
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace adugs::data {

// Kinematic state of the body frame B in the world W at one instant.
struct SimBodyState {
  int64_t t_ns = 0;
  Eigen::Vector3d p_W_B = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_W_B = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();      // d p_W_B / dt
  Eigen::Vector3d a_W = Eigen::Vector3d::Zero();      // d v_W / dt
  Eigen::Vector3d omega_B = Eigen::Vector3d::Zero();  // body rate: R_W_B^T dR_W_B/dt = [omega_B]x
};

// Anything that gives the body state at a time (synthetic or interpolated from a file).
class SimTrajectory {
 public:
  virtual ~SimTrajectory() = default;
  virtual SimBodyState stateAt(int64_t t_ns) const = 0;
  virtual int64_t startNs() const = 0;
  virtual int64_t endNs() const = 0;
};

// One scalar channel: offset + rate * t + sum_k amp_k * sin(freq_k * t + phase_k), t in seconds
// since the trajectory start; freq in rad/s.
struct SineChannel {
  struct Term {
    double amp = 0, freq = 0, phase = 0;
  };
  double offset = 0;
  double rate = 0;
  std::vector<Term> terms;

  // value, first and second derivative at t.
  Eigen::Vector3d eval(double t) const;
};

// Position (x, y, z) and ZYX Euler angles (yaw, pitch, roll: R = Rz(yaw) Ry(pitch) Rx(roll)), each
// a sum of sines: smooth, bounded, with closed-form velocity, acceleration and body rate.
class SineTrajectory : public SimTrajectory {
 public:
  enum Channel { kX = 0, kY, kZ, kYaw, kPitch, kRoll };

  SineTrajectory(int64_t start_ns, int64_t end_ns, std::array<SineChannel, 6> channels);

  SimBodyState stateAt(int64_t t_ns) const override;
  int64_t startNs() const override { return start_ns_; }
  int64_t endNs() const override { return end_ns_; }
  const std::array<SineChannel, 6>& channels() const { return channels_; }

 private:
  int64_t start_ns_, end_ns_;
  std::array<SineChannel, 6> channels_;
};

// Rotation Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d eulerZyxToRotation(double yaw, double pitch, double roll);

}  // namespace adugs::data
