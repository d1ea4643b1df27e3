#include "vio/frontend/feature_tracker_options.h"

#include "data/formats/yaml_options.h"

namespace adugs::vio {

void readFeatureTrackerOptions(data::YamlOptionsReader& r, FeatureTrackerOptions* o) {
  r.optional("max_features", o->max_features, 1, 100000);
  r.optional("min_distance_px", o->min_distance_px, 0.0, 1000.0);
  r.optional("klt_window_px", o->klt_window_px, 3, 101);
  r.optional("klt_pyramid_levels", o->klt_pyramid_levels, 0, 8);
  r.optional("klt_min_eigen", o->klt_min_eigen, 0.0, 1.0);
  r.optional("border_px", o->border_px, 0.0, 100.0);
  r.optional("anchor_alignment", o->anchor_alignment);
  r.optional("anchor_patch_half_px", o->anchor_patch_half_px, 2, 30);
  r.optional("anchor_max_correction_px", o->anchor_max_correction_px, 0.0, 100.0);
  r.optional("anchor_min_zncc", o->anchor_min_zncc, -1.0, 1.0);
  r.optional("anchor_max_scale", o->anchor_max_scale, 1.0, 10.0);
  r.optional("fb_check", o->fb_check);
  r.optional("fb_threshold_px", o->fb_threshold_px, 0.0, 100.0);
  r.optional("fb_pyramid_levels", o->fb_pyramid_levels, 0, 8);
  r.optional("ransac", o->ransac);
  r.optional("ransac_threshold_px", o->ransac_threshold_px, 1e-3, 100.0);
  r.optional("ransac_confidence", o->ransac_confidence, 0.5, 0.999999);
  r.optional("fast_threshold", o->fast_threshold, 1, 255);
  r.optional("max_candidates", o->max_candidates, 1, 1000000);
  r.optional("detection_border_px", o->detection_border_px, 0, 200);
}

FeatureTrackerOptions parseFeatureTrackerOptions(const std::string& text,
                                                 const std::string& source) {
  FeatureTrackerOptions o;
  data::YamlOptionsReader r = data::YamlOptionsReader::fromString(text, source);
  readFeatureTrackerOptions(r, &o);
  r.finish();
  return o;
}

FeatureTrackerOptions loadFeatureTrackerOptions(const std::string& path) {
  FeatureTrackerOptions o;
  data::YamlOptionsReader r = data::YamlOptionsReader::fromFile(path);
  readFeatureTrackerOptions(r, &o);
  r.finish();
  return o;
}

}  // namespace adugs::vio
