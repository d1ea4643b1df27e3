#pragma once
// ViSP camera XML (vpXmlParserCamera) for a calibrated pinhole camera.
//
// ViSP's distortion model differs from Kalibr's: one radial coefficient each way,
// u = u0 + px * x * (1 + kud * r^2) (undistorted -> distorted) and its approximate inverse kdu.
// So we always write "perspectiveProjWithoutDistortion" (px, py, u0, v0), which is exact for
// undistorted images, with an XML comment carrying the full Kalibr model. Only when the model
// is radtan with k2 = p1 = p2 = 0 do we also write "perspectiveProjWithDistortion": kud = k1 is
// then exact, and kdu is a least-squares fit of the inverse over the image.
#include <string>

#include "calib/calib_camera.h"

namespace adugs::calib {

// note: extra text for the XML comment (e.g. the calibration's verdict). Throws
// data::InputError if the file cannot be written, std::invalid_argument for a camera that is not
// pinhole (ViSP 3.5 has no unified, double-sphere or EUCM camera).
void writeVispCameraXml(const std::string& path, const CalibCamera& camera,
                        const std::string& camera_name = "Camera", const std::string& note = "");

}  // namespace adugs::calib
