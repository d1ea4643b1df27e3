#pragma once
// The pipeline's last stage, on a thread of its own: the sliding-window visual-inertial estimator
// (vio/estimator/sliding_window_estimator.h) on each tracked frame and the IMU samples it carries,
// one TUM pose per estimated frame (flushed), the gyro bias fed back to the stages ahead, the
// run's statistics; frames then go on to the view when there is one.
// Vision-only runs (no IMU: a video, a webcam) have no estimator: the stage only counts.
//
// test_delay_ms (run config `pipeline: test_estimator_delay_ms`) is for tests only: a sleep per
// frame that makes the estimator slower than the camera, to check the live drop policy.
#include <memory>
#include <string>

#include "app/pipeline/estimator_feedback.h"
#include "app/pipeline/channel.h"
#include "app/pipeline/pipeline_stats.h"
#include "data/formats/trajectory_io.h"
#include "vio/estimator/sliding_window_estimator.h"

namespace adugs::app {

class EstimatorStage {
 public:
  // estimator nullptr: vision only (trajectory_path unused).
  EstimatorStage(std::unique_ptr<vio::SlidingWindowEstimator> estimator, const std::string& trajectory_path,
                 double test_delay_ms);

  // Until `in` is drained or `view` closed; then closes `view` and the trajectory file, and
  // publishes the bias after every frame (closing `biases` at the end). live: the view never holds
  // the pipeline back, frames it is not ready for are not drawn (counted); playback: it gets every
  // frame. Exceptions propagate.
  void run(Channel<PipelineFrame>& in, Channel<PipelineFrame>* view, EstimatorFeedback* biases,
           PipelineCounters& counters, bool live);

  const PipelineStats& stats() const { return stats_; }  // after run()
  const vio::SlidingWindowEstimator* estimator() const { return estimator_.get(); }

 private:
  std::unique_ptr<vio::SlidingWindowEstimator> estimator_;
  std::unique_ptr<data::TumTrajectoryWriter> writer_;
  double test_delay_ms_;
  PipelineStats stats_;
};

}  // namespace adugs::app
