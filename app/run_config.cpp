#include "app/run_config.h"

#include "data/yaml_options.h"

namespace adugs::app {

RunConfig loadRunConfig(const std::string& path) {
  RunConfig c;
  if (path.empty()) return c;
  data::YamlOptionsReader r = data::YamlOptionsReader::fromFile(path);
  if (r.has("tracker")) {
    data::YamlOptionsReader t = r.child("tracker");
    vio::readFeatureTrackerOptions(t, &c.tracker);
    t.finish();
  }
  if (r.has("estimator")) {
    data::YamlOptionsReader e = r.child("estimator");
    vio::readEstimatorOptions(e, &c.estimator);
    e.finish();
  }
  r.finish();
  return c;
}

}  // namespace adugs::app
