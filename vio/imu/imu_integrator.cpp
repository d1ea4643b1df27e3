#include "vio/imu/imu_integrator.h"

#include <cmath>
#include <stdexcept>

namespace adugs::vio {

NavState propagateMidpoint(const NavState& state, const data::ImuSample& a,
                           const data::ImuSample& b, const Eigen::Vector3d& g_W) {
  if (b.t_ns <= a.t_ns) throw std::invalid_argument("IMU samples must be strictly increasing");
  const double dt = data::nsToSec(b.t_ns - a.t_ns);
  NavState next = state;
  next.t_ns = b.t_ns;
  const Eigen::Vector3d acc_a = state.q_W_B * (a.accel - state.accel_bias) + g_W;
  const Eigen::Vector3d omega = 0.5 * (a.gyro + b.gyro) - state.gyro_bias;
  next.q_W_B = (state.q_W_B * quaternionExp(omega * dt)).normalized();
  const Eigen::Vector3d acc_b = next.q_W_B * (b.accel - state.accel_bias) + g_W;
  const Eigen::Vector3d acc = 0.5 * (acc_a + acc_b);
  next.p_W_B = state.p_W_B + state.v_W * dt + 0.5 * acc * dt * dt;
  next.v_W = state.v_W + acc * dt;
  return next;
}

}  // namespace adugs::vio
