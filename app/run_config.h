#pragma once
// The configuration of `adugs run --config FILE` (data/config/*.yaml): one map per stage,
//   tracker:   vio/feature_tracker_options.h keys
//   estimator: vio/estimator_options.h keys (static_init:, init: nested)
// Every key is optional; unknown keys and out-of-range values are errors naming file, line, key.
#include <string>

#include "vio/estimator_options.h"
#include "vio/feature_tracker_options.h"

namespace adugs::app {

struct RunConfig {
  vio::FeatureTrackerOptions tracker;
  vio::EstimatorOptions estimator;
};

RunConfig loadRunConfig(const std::string& path);  // "" = defaults

}  // namespace adugs::app
