#pragma once
// EuRoC/ASL IMU files, imu0/data.csv: "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z" (rad/s, m/s^2),
// read whole: the simulator's hybrid mode and the IMU calibrations take the stream at once (the
// sequence readers stream it row by row instead).
#include <string>
#include <vector>

#include "data/types.h"

namespace adugs::data {

// Throws InputError naming the file, line and column on bad rows, non-increasing time or an
// empty file.
std::vector<ImuSample> readEurocImuCsv(const std::string& path);

}  // namespace adugs::data
