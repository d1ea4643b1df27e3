#include "tracking/dynamic_masker_options.h"

#include <cmath>
#include <string>
#include <vector>

namespace adugs::tracking {

void readDynamicMaskerOptions(data::YamlOptionsReader& d, DynamicMaskerOptions* options) {
  DynamicMaskerOptions& o = *options;
  d.optional("detect_every", o.detect_every, 1, 1000);
  std::string tracker = "sort", noise = "adaptive";
  d.optional("tracker", tracker);
  if (tracker != "sort" && tracker != "none") d.fail("tracker", "must be sort or none");
  o.track = tracker == "sort";
  d.optional("noise", noise);
  if (noise != "adaptive" && noise != "fixed") d.fail("noise", "must be adaptive or fixed");
  d.optional("max_age", o.sort.max_age, 0, 1000);
  d.optional("min_hits", o.sort.min_hits, 0, 1000);
  d.optional("iou_min", o.sort.iou_min, 0.0, 1.0);
  d.optional("lambda", o.sort.filter.lambda, 1e-6, 1e6);
  d.optional("beta_pos", o.sort.filter.beta_pos, 1e-6, 1e6);
  d.optional("beta_size", o.sort.filter.beta_size, 1e-6, 1e6);
  d.optional("window", o.sort.filter.window, 1, 1000);
  if (noise == "fixed") o.sort.filter.lambda = 1e6;  // erf saturates at once: R = beta, a fixed R
  d.optional("erode_radius_px", o.refinement.erode_radius_px, 0, 100);
  d.optional("dilate_radius_px", o.refinement.dilate_radius_px, 0, 200);
  d.optional("min_box_side_px", o.min_box_side_px, 0.0, 1000.0);
  d.optional("segment_every", o.segment_every, 0, 1000);
  d.optional("segment_async", o.segment_async);
  d.optional("camera_motion_compensation", o.camera_motion_compensation);
  d.optional("appearance_weight", o.sort.appearance_weight, 0.0, 10.0);
  d.optional("high_score", o.sort.high_score, 0.0, 1.0);
  d.optional("low_iou_min", o.sort.low_iou_min, 0.0, 1.0);
  d.optional("drop_unconfirmed", o.sort.drop_unconfirmed_on_miss);
  d.optional("last_box_association", o.sort.last_box_association);
  d.optional("direction_weight", o.sort.direction_weight, 0.0, 10.0);
  d.optional("direction_frames", o.sort.direction_frames, 1, 100);
  d.optional("recovery", o.sort.observation_centric_recovery);
  if (!o.track && o.detect_every != 1) d.fail("detect_every", "detecting every n-th frame needs tracker: sort");
  d.optional("static_after_frames", o.object_motion.static_frames, 0, 100000);
  d.optional("static_min_points", o.object_motion.min_points, 1, 1000);
  d.optional("static_range_tolerance", o.object_motion.range_tolerance, 1.0, 10.0);
  d.optional("static_min_slide_px", o.object_motion.min_slide_px, 0.0, 1000.0);
  // [[class id, height m], ...]: the classes a moving camera can judge static by their size.
  std::vector<std::vector<double>> heights;
  if (d.optional("static_class_heights_m", heights)) {
    o.object_motion.class_height_m.clear();
    for (const std::vector<double>& h : heights) {
      if (h.size() != 2 || h[0] < 0 || h[0] != std::floor(h[0]) || !(h[1] > 0 && h[1] <= 100))
        d.fail("static_class_heights_m", "must be pairs [class id (integer >= 0), height in metres (0, 100]]");
      o.object_motion.class_height_m[static_cast<int>(h[0])] = h[1];
    }
  }
  if (d.has("motion_cue")) {
    data::YamlOptionsReader m = d.child("motion_cue");
    MotionCueOptions& c = o.motion_cue;
    m.optional("cell_px", c.cell_px, 4, 1000);
    m.optional("klt_window_px", c.klt_window_px, 5, 101);
    m.optional("klt_pyramid_levels", c.klt_pyramid_levels, 0, 6);
    m.optional("still_pyramid_levels", c.still_pyramid_levels, 0, 6);
    m.optional("corner_quality", c.corner_quality, 1e-12, 1.0);  // MotionCue needs > 0
    m.optional("threshold_px", c.threshold_px, 0.01, 100.0);
    m.optional("strong_threshold_px", c.strong_threshold_px, 0.01, 1000.0);
    m.optional("translation_min_gain", c.translation_min_gain, 0.0, 1.0);
    m.optional("min_speed", c.min_speed, 0.0, 100.0);
    m.optional("ransac_iterations", c.ransac_iterations, 1, 100000);
    m.optional("group_radius_px", c.group_radius_px, 1.0, 10000.0);
    m.optional("min_points", c.min_points, 1, 1000);
    m.optional("min_corner_points", c.min_corner_points, 0, 1000);
    m.optional("corner_ratio", c.corner_ratio, 0.0, 1.0);
    m.optional("box_margin", c.box_margin, 0.0, 10.0);
    if (c.strong_threshold_px < c.threshold_px) m.fail("strong_threshold_px", "must be at least threshold_px");
    m.finish();
  }
  if (d.has("grabcut")) {
    data::YamlOptionsReader g = d.child("grabcut");
    GrabCutOptions& c = o.grabcut;
    g.optional("iterations", c.iterations, 1, 100);
    g.optional("max_side", c.max_side, 16, 4096);
    g.optional("prompted_iterations", c.prompted_iterations, 1, 100);
    g.optional("prompted_max_side", c.prompted_max_side, 16, 4096);
    g.optional("margin", c.margin, 0.0, 10.0);
    g.optional("min_box_side", c.min_box_side, 0, 10000);
    g.optional("min_foreground_fraction", c.min_foreground_fraction, 0.0, 0.99);
    g.optional("point_radius_px", c.point_radius_px, 0.0, 1000.0);
    g.finish();
  }
}

}  // namespace adugs::tracking
