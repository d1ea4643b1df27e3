#include "data/calibration.h"

namespace adugs::data {

std::string toString(DistortionModel model) {
  return model == DistortionModel::kEquidistant ? "equidistant" : "radial-tangential";
}

}  // namespace adugs::data
