#pragma once
// What masks the frames: nothing, the simulator's ground-truth masks (mav0/mask0), the detector
// chain (tracking/dynamic_masker.h; with the motion cue's boxes too unless told not), or the same
// chain prompted by the class-free motion cue alone (tracking/detect/motion_cue.h). On the command
// line: --mask none | gt | detector | motion.
#include <map>
#include <string>

namespace adugs::app {

enum class MaskSource { kNone, kGroundTruth, kDetector, kMotion };

// The command line's names of each source ("none", "gt", "detector", "motion").
const std::map<std::string, MaskSource>& maskSourceNames();
std::string maskSourceName(MaskSource source);

}  // namespace adugs::app
