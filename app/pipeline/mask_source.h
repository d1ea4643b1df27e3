#pragma once
// What masks the frames: nothing, the simulator's ground-truth masks (mav0/mask0), or the
// detector chain (tracking/dynamic_masker.h). On the command line: --mask none | gt | detector.
#include <map>
#include <string>

namespace adugs::app {

enum class MaskSource { kNone, kGroundTruth, kDetector };

// The command line's names of each source ("none", "gt", "detector").
const std::map<std::string, MaskSource>& maskSourceNames();
std::string maskSourceName(MaskSource source);

}  // namespace adugs::app
