#pragma once
// What `adugs d435i info` prints: every RealSense camera the kernel shows (by USB id), its V4L2
// nodes with their formats, sizes and rates, the D4xx controls' current values, its IIO devices
// with their scan elements, rates, scales and timestamp clock, the IMU scale the data width
// implies, the nodes the options would use, and whether this user may open them. With a stream
// check: the measured frame and IMU rates, drops and the camera clock's drift over some seconds.
#include <ostream>

#include "data/device/v4l2_io.h"
#include "data/sources/d435i_options.h"

namespace adugs::data {

// InputError when no camera matches options.usb_id (the message lists the USB video devices seen).
void printD435iInfo(std::ostream& out, const D435iOptions& options, V4l2Io& io);

// Streams with `options` for `seconds` and prints what came (the source's counts and rates).
void printD435iStreamCheck(std::ostream& out, const D435iOptions& options, double seconds, V4l2Io& io);

}  // namespace adugs::data
