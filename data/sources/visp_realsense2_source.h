#pragma once
// The D435i through librealsense, for builds whose ViSP was compiled with it (VISP_HAVE_REALSENSE2;
// Debian's ViSP is not, so on Debian 12 this path is compiled out and was never built or run by
// this project's CI: it is kept for users with their own ViSP). It opens the camera with
// vpRealSense2::open(config, callback), the librealsense pipeline callbacks (ViSP 3.5's IMU getters
// poll wait_for_frames and lose samples), and hands out the same stream as D435iSource: the left
// infrared image stamped at the middle of its exposure, the accelerometer united onto the gyro
// stamps, both on CLOCK_MONOTONIC, in time order. librealsense already turns the IMU into SI units
// in the depth camera's axes, which is this project's IMU frame convention for the D435i.
#include <memory>

#include "data/sources/d435i_options.h"
#include "data/sources/sequence_source.h"

namespace adugs::data {

// Whether this build has the vpRealSense2 path.
bool vispRealSense2Available();

// The source (InputError naming d435i.backend when this build lacks it, or when the camera cannot
// be opened). `image_time_shift_ns` is added to frame stamps (Kalibr's timeshift_cam_imu).
std::unique_ptr<data::SequenceSource> openVispRealSense2(const D435iOptions& options, int64_t image_time_shift_ns);

}  // namespace adugs::data
