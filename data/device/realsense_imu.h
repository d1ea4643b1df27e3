#pragma once
// Units and axes of the RealSense D4xx IMU (Bosch BMI055 / BMI085) as its HID sensors report it,
// following librealsense's motion-transform.cpp and d400-motion.cpp:
//
//   accelerometer  0.001 g per LSB (g = 9.80665 m/s^2), 16-bit values (32-bit from firmware 5.16)
//   gyroscope      0.1 deg/s per LSB with 16-bit values (firmware before 5.16),
//                  0.0001 deg/s per LSB with 32-bit values (firmware 5.16 and later)
// The kernel's hid-sensor drivers size each scan element by the HID report field, so the scan
// element's real bits (in_anglvel_x_type "le:s16/32>>0" vs "le:s32/32>>0") tell which firmware
// scale applies without asking the firmware for its version.
//
// Axes: librealsense rotates the IMU's raw axes into the depth (left infrared) camera's frame
// (x right, y down, z forward) with diag(-1, 1, -1) for the D435i, D455 and later units
// (ds-calib-parsers.cpp, `_imu_2_depth_rot`); after it a camera lying on its back (lens up)
// reads +9.81 m/s^2 on z (specific force). This project's IMU/body frame B is that rotated frame.
#include <Eigen/Core>

namespace adugs::data {

constexpr double kStandardGravity = 9.80665;                         // m/s^2
constexpr double kRealsenseAccelLsb = 0.001 * kStandardGravity;      // m/s^2 per LSB
constexpr double kRealsenseGyroLsbDeg16 = 0.1;                       // deg/s per LSB, 16-bit data
constexpr double kRealsenseGyroLsbDeg32 = 0.0001;                    // deg/s per LSB, 32-bit data

// deg/s per LSB for a gyro scan element with `real_bits` meaningful bits (16 or 32); 0 for other
// widths (the caller reports it: an unknown firmware).
double realsenseGyroLsbDegPerSec(int real_bits);

// Raw counts (IMU axes) -> SI units in the camera-aligned frame B.
Eigen::Vector3d realsenseAccelToBody(const Eigen::Vector3d& counts);
Eigen::Vector3d realsenseGyroToBody(const Eigen::Vector3d& counts, double gyro_lsb_deg_per_s);

// The raw-axes -> camera-axes rotation diag(-1, 1, -1).
Eigen::Vector3d realsenseImuAxesToCamera(const Eigen::Vector3d& v);

}  // namespace adugs::data
