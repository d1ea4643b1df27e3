#include "vio/estimator/estimator_options.h"

#include <algorithm>
#include <cmath>

#include "data/formats/yaml_options.h"

namespace adugs::vio {

void readEstimatorOptions(data::YamlOptionsReader& r, EstimatorOptions* o) {
  r.optional("window_size", o->window_size, 4, 40);
  r.optional("keyframe_parallax_px", o->keyframe_parallax_px, 0.0, 200.0);
  r.optional("keyframe_min_tracked", o->keyframe_min_tracked, 0, 10000);
  r.optional("pixel_sigma", o->pixel_sigma, 0.01, 100.0);
  r.optional("huber_px", o->huber_px, 0.01, 100.0);
  r.optional("accel_noise_inflation", o->accel_noise_inflation, 0.1, 100.0);
  r.optional("outlier_reprojection_px", o->outlier_reprojection_px, 0.0, 1000.0);
  r.optional("max_iterations", o->max_iterations, 1, 1000);
  r.optional("solver_function_tolerance", o->solver_function_tolerance, 0.0, 0.5);
  r.optional("max_solver_time_s", o->max_solver_time_s, 0.001, 10.0);
  r.optional("min_depth_m", o->min_depth_m, 0.001, 1000.0);
  r.optional("max_depth_m", o->max_depth_m, 0.01, 1e5);
  r.optional("min_triangulation_angle_deg", o->min_triangulation_angle_deg, 0.0, 45.0);
  r.optional("zero_velocity_updates", o->zero_velocity_updates);
  r.optional("zero_velocity_sigma", o->zero_velocity_sigma, 1e-5, 10.0);
  r.optional("gyro_bias_at_rest", o->gyro_bias_at_rest);
  r.optional("static_init_accel_bias_sigma", o->static_init_accel_bias_sigma, 0.0, 10.0);
  r.optional("vi_init_accel_bias_sigma", o->vi_init_accel_bias_sigma, 0.0, 10.0);
  r.optional("stationary_parallax_px", o->stationary_parallax_px, 0.0, 100.0);
  r.optional("first_estimate_jacobians", o->first_estimate_jacobians);
  r.optional("report_relative_covariance", o->report_relative_covariance);
  r.optional("max_accel_bias", o->max_accel_bias, 0.01, 100.0);
  r.optional("max_gyro_bias", o->max_gyro_bias, 0.001, 100.0);
  r.optional("max_speed", o->max_speed, 0.1, 1000.0);
  r.optional("max_position_jump", o->max_position_jump, 0.01, 1000.0);
  r.optional("min_tracked_features", o->min_tracked_features, 0, 10000);
  r.optional("few_features_max_s", o->few_features_max_s, 0.0, 60.0);
  r.optional("max_imu_gap_s", o->max_imu_gap_s, 0.001, 10.0);
  r.optional("estimate_extrinsic", o->estimate_extrinsic);
  r.optional("extrinsic_prior_sigma_m", o->extrinsic_prior_sigma_m, 1e-4, 10.0);
  r.optional("extrinsic_prior_sigma_deg", o->extrinsic_prior_sigma_deg, 0.01, 90.0);
  r.optional("time_offset_s", o->time_offset_s, -1.0, 1.0);
  r.optional("estimate_time_offset", o->estimate_time_offset);
  r.optional("time_offset_prior_sigma_s", o->time_offset_prior_sigma_s, 1e-5, 1.0);
  r.optional("max_time_offset_s", o->max_time_offset_s, 1e-4, 1.0);
  r.optional("time_offset_warmup_s", o->time_offset_warmup_s, 0.0, 600.0);
  r.optional("init_min_span_s", o->init_min_span_s, 0.0, 30.0);
  r.optional("init_window_size", o->init_window_size, 4, 40);
  r.optional("reset_dead_reckoning_max_s", o->reset_dead_reckoning_max_s, 0.0, 600.0);
  if (std::abs(o->time_offset_s) >= o->max_time_offset_s)
    r.fail("time_offset_s", "must lie within +-max_time_offset_s");
  if (o->max_depth_m <= o->min_depth_m) r.fail("max_depth_m", "must exceed min_depth_m");
  if (r.has("static_init")) {
    data::YamlOptionsReader s = r.child("static_init");
    s.optional("window_s", o->static_init.window_s, 0.05, 60.0);
    s.optional("max_accel_std", o->static_init.max_accel_std, 0.0, 100.0);
    s.optional("max_gyro_std", o->static_init.max_gyro_std, 0.0, 10.0);
    s.optional("max_parallax_px", o->static_init.max_parallax_px, 0.0, 100.0);
    s.finish();
  }
  if (r.has("init")) {
    data::YamlOptionsReader s = r.child("init");
    s.optional("min_frames", o->init.min_frames, 3, 100);
    s.optional("min_common_features", o->init.min_common_features, 8, 10000);
    s.optional("min_parallax_px", o->init.min_parallax_px, 0.0, 1000.0);
    s.optional("max_reprojection_px", o->init.max_reprojection_px, 0.01, 100.0);
    s.optional("min_imu_excitation", o->init.min_imu_excitation, 0.0, 100.0);
    s.optional("max_scale_relative_std", o->init.max_scale_relative_std, 0.0, 100.0);
    s.finish();
  }
  if (o->init.min_frames > o->window_size) r.fail("init", "init.min_frames exceeds window_size");
  if (o->init.min_frames > std::min(o->init_window_size, o->window_size))
    r.fail("init", "init.min_frames exceeds init_window_size");
}

}  // namespace adugs::vio
