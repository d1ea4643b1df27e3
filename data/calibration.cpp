#include "data/calibration.h"

namespace adugs::data {

std::string toString(DistortionModel model) {
  switch (model) {
    case DistortionModel::kEquidistant: return "equidistant";
    case DistortionModel::kNone: return "none";
    case DistortionModel::kRadialTangential: break;
  }
  return "radial-tangential";
}

std::string toString(ProjectionModel model) {
  switch (model) {
    case ProjectionModel::kUnified: return "omni";
    case ProjectionModel::kDoubleSphere: return "ds";
    case ProjectionModel::kExtendedUnified: return "eucm";
    case ProjectionModel::kPinhole: break;
  }
  return "pinhole";
}

int projectionParameterCount(ProjectionModel model) {
  switch (model) {
    case ProjectionModel::kUnified: return 1;
    case ProjectionModel::kDoubleSphere:
    case ProjectionModel::kExtendedUnified: return 2;
    case ProjectionModel::kPinhole: break;
  }
  return 0;
}

}  // namespace adugs::data
