#pragma once
// The same lens in another camera model: a user with a Kalibr radtan calibration who wants to
// give Basalt (which has no radtan) a double-sphere one, or a sequence rendered through each
// model of one physical lens. The fit is on rays, not on a target: every pixel of a grid over
// the image (step grid_step_px) is unprojected through the source camera, and the target model's
// parameters (fx fy cx cy, its projection parameters, its 4 distortion coefficients) minimise the
// pixel distance between where the target projects those rays and the pixel (Ceres, autodiff of
// data::projectPoint). Pixels the source has no ray for (outside a fisheye's image circle) are
// left out; rays the target cannot project make its step fail (Ceres then shortens it).
//
// Starts: fx fy cx cy from the source, scaled so the focal length on the optical axis matches
// (the target's on-axis focal is fx / (1 + xi) for omni and ds); omni xi 0 (omni with xi 0 IS
// pinhole radtan), ds xi 0 and alpha 0.5, eucm alpha 0.5 and beta 1 (both then pinhole near the
// axis), distortion coefficients 0.
#include <string>
#include <vector>

#include "data/calibration.h"

namespace adugs::calib {

// A camera model by the name users give it (Kalibr's and Basalt's):
//   radtan       pinhole + radial-tangential       equidistant  pinhole + equidistant (KB4)
//   pinhole      pinhole, no distortion            omni         unified (MEI) + radtan
//   ds           double sphere                     eucm         extended unified
//   omni-none    unified (MEI) without distortion
struct LensModel {
  data::ProjectionModel projection = data::ProjectionModel::kPinhole;
  data::DistortionModel distortion = data::DistortionModel::kRadialTangential;
};
// False for a name not above.
bool parseLensModel(const std::string& name, LensModel& out);
std::vector<std::string> lensModelNames();
// The name of a camera's model as above.
std::string lensModelName(const data::CameraCalibration& camera);

struct LensRefitOptions {
  double grid_step_px = 8;   // pixel grid spacing
  int max_iterations = 200;
};

struct LensRefit {
  data::CameraCalibration camera;  // the source's size, rate and T_B_C; the target's lens
  double rms_px = 0;               // over the grid
  double max_px = 0;
  int pixels = 0;                  // grid pixels with a source ray
};

// Throws std::invalid_argument for a source that cannot be used (no pixel with a ray), and
// std::runtime_error when Ceres finds no usable solution.
LensRefit refitLens(const data::CameraCalibration& source, const LensModel& target,
                    const LensRefitOptions& options = {});

}  // namespace adugs::calib
