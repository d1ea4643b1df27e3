#pragma once
// What the pipeline counts: live counters the status line reads while it runs (atomics, written by
// the stages), and the per-frame figures the run summary reports (gathered by the last stage).
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "app/pipeline/pipeline_frame.h"

namespace adugs::app {

struct PipelineCounters {
  std::atomic<size_t> frames_acquired{0}, imu_acquired{0};
  std::atomic<size_t> frames_processed{0};  // through the last stage
  std::atomic<int> features{0};             // in the last frame processed
  std::atomic<int> resets{0};
  std::atomic<bool> estimating{false};  // an estimator runs (else vision only)
  std::atomic<bool> initialized{false};
  std::atomic<int64_t> sequence_ns{0};  // of the last frame processed, since the first measurement
};

struct PipelineStats {
  size_t frames = 0;            // processed by every stage
  size_t poses = 0;             // estimated
  size_t imu_to_estimator = 0;  // IMU samples the estimator was given
  size_t view_frames_skipped = 0;  // live: frames the view was not ready to draw
  double sequence_s = 0;        // of the last frame processed
  // mask: detection + SORT/segmentation/refinement (the dynamic-mask chain); latency: source -> estimated
  std::vector<double> frontend_ms, backend_ms, detect_ms, segment_ms, mask_ms, latency_ms;
  std::vector<double> dynamic_drop, masked_fraction, features;
  double exact_pixels = 0, exact_covered = 0, masked_pixels = 0;
  double exact_covered_motion = 0, masked_motion = 0, exact_covered_detector = 0, masked_detector = 0;
  std::map<int, std::pair<double, double>> exact_by_class;  // COCO id -> (exact pixels in its boxes, masked)
  size_t objects_seen_static = 0;

  void record(const PipelineFrame& f, double latency) {
    ++frames;
    sequence_s = f.sequence_s;
    frontend_ms.push_back(f.frontend_ms);
    latency_ms.push_back(latency);
    dynamic_drop.push_back(f.dropped_dynamic);
    features.push_back(static_cast<double>(f.features.size()));
    if (f.mask_ms >= 0) {
      if (f.detections) detect_ms.push_back(f.detect_ms);
      segment_ms.push_back(f.mask_ms);
      mask_ms.push_back(f.detect_ms + f.mask_ms);
      masked_fraction.push_back(f.masked_fraction);
      exact_pixels += f.exact_pixels;
      exact_covered += f.exact_covered;
      masked_pixels += f.masked_pixels;
      exact_covered_motion += f.exact_covered_motion;
      masked_motion += f.masked_motion;
      exact_covered_detector += f.exact_covered_detector;
      masked_detector += f.masked_detector;
      for (const auto& [cls, pixels] : f.exact_by_class) {
        exact_by_class[cls].first += pixels.first;
        exact_by_class[cls].second += pixels.second;
      }
      objects_seen_static = f.objects_seen_static;
    }
  }
};

}  // namespace adugs::app
