#pragma once
// Options of the KLT + ORB/ANMS front-end (FeatureTracker), defaults in code, overridable from
// YAML. Unknown keys and out-of-range values are data::InputError naming the file, line and key.
//
//   max_features: 200
//   min_distance_px: 20
//   fb_threshold_px: 0.5
// (every field below is a key of the same name).
#include <string>

namespace adugs::data {
class YamlOptionsReader;
}

namespace adugs::vio {

struct FeatureTrackerOptions {
  // Feature budget and spacing.
  int max_features = 200;       // N_max: features held after every frame (when texture allows)
  double min_distance_px = 20;  // D_min: between new points, and from new points to tracked ones

  // Pyramidal KLT (ViSP vpKltOpencv).
  int klt_window_px = 15;       // square search window at each level (21: +1 ms, no gain here)
  int klt_pyramid_levels = 3;   // highest pyramid level (0 = full resolution only), OpenCV maxLevel
  double klt_min_eigen = 1e-4;  // OpenCV's minEigThreshold: drops points on textureless patches
  double border_px = 1.0;       // tracked points closer than this to the image edge are lost

  // Anchor alignment (vio/frontend/anchor_patch.h): every frame, refine each KLT position by an affine
  // alignment of the patch where the feature was first seen, so track errors do not add up. A
  // fit that moves the point more than anchor_max_correction_px, correlates below
  // anchor_min_zncc or scales the patch beyond anchor_max_scale (or 1 / it) re-anchors the
  // feature at its KLT position instead.
  bool anchor_alignment = true;
  int anchor_patch_half_px = 8;  // patch (2 h + 1)^2
  double anchor_max_correction_px = 1.0;
  double anchor_min_zncc = 0.9;
  double anchor_max_scale = 1.5;

  // Forward-backward check: track back into the previous image, reject if the round trip misses
  // the start by more than fb_threshold_px.
  bool fb_check = true;
  double fb_threshold_px = 0.5;
  int fb_pyramid_levels = 0;  // the backward pass starts at the answer: no pyramid needed

  // RANSAC (OpenCV USAC) on the fundamental matrix of undistorted points scaled by the mean
  // focal length, so the threshold is in pixels of an ideal pinhole camera (VINS-Mono's
  // F_THRESHOLD).
  bool ransac = true;
  double ransac_threshold_px = 1.0;
  double ransac_confidence = 0.99;

  // New points: ORB's FAST detector (FAST score, one pyramid level), then ANMS.
  int fast_threshold = 10;       // low: EuRoC-like scenes have large weakly textured areas
  int max_candidates = 4000;     // strongest FAST corners handed to ANMS (too few: they all
                                 // cluster on the most textured objects)
  int detection_border_px = 16;  // no new points closer than this to the image edge
};

// Reads the keys above from a reader (e.g. a child map of a bigger config); call finish() after.
void readFeatureTrackerOptions(data::YamlOptionsReader& reader, FeatureTrackerOptions* options);
// A whole YAML file of these keys; unknown keys are an error.
FeatureTrackerOptions loadFeatureTrackerOptions(const std::string& path);
FeatureTrackerOptions parseFeatureTrackerOptions(const std::string& text,
                                                 const std::string& source);

}  // namespace adugs::vio
