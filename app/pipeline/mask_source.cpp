#include "app/pipeline/mask_source.h"

namespace adugs::app {

const std::map<std::string, MaskSource>& maskSourceNames() {
  static const std::map<std::string, MaskSource> names = {
      {"none", MaskSource::kNone}, {"gt", MaskSource::kGroundTruth}, {"detector", MaskSource::kDetector},
      {"motion", MaskSource::kMotion}};
  return names;
}

std::string maskSourceName(MaskSource source) {
  for (const auto& [name, value] : maskSourceNames())
    if (value == source) return name;
  return "?";
}

}  // namespace adugs::app
