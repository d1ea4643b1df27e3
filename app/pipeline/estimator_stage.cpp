#include "app/pipeline/estimator_stage.h"

#include <chrono>
#include <thread>

#include "data/elapsed_time.h"

namespace adugs::app {

EstimatorStage::EstimatorStage(std::unique_ptr<vio::SlidingWindowEstimator> estimator,
                               const std::string& trajectory_path, double test_delay_ms)
    : estimator_(std::move(estimator)), test_delay_ms_(test_delay_ms) {
  if (estimator_) writer_ = std::make_unique<data::TumTrajectoryWriter>(trajectory_path);
}

void EstimatorStage::run(Channel<PipelineFrame>& in, Channel<PipelineFrame>* view, EstimatorFeedback* biases,
                         PipelineCounters& counters, bool live) {
  counters.estimating = estimator_ != nullptr;
  PipelineFrame f;
  while (in.pop(&f)) {
    if (test_delay_ms_ > 0) std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(test_delay_ms_));
    if (estimator_) {
      for (const data::ImuSample& s : f.imu) estimator_->addImu(s);
      stats_.imu_to_estimator += f.imu.size();
      const auto t0 = std::chrono::steady_clock::now();
      const auto state = estimator_->addFrame(f.features);
      f.backend_ms = data::msSince(t0);
      stats_.backend_ms.push_back(f.backend_ms);
      if (biases) {
        std::optional<vio::NavState> after;
        if (state) after = vio::NavState{state->t_ns, state->q_W_B, state->p_W_B, state->v_W, state->gyro_bias,
                                         state->accel_bias};
        biases->publish(estimator_->gyroBias(), after, f.frame.t_ns);
      }
      if (state) {
        data::StampedPose p;
        p.t_ns = state->t_ns;
        p.p_W_B = state->p_W_B;
        p.q_W_B = state->q_W_B;
        writer_->write(p);
        f.pose = p;
        ++stats_.poses;
      }
      counters.initialized = estimator_->initialized();
      counters.resets = estimator_->stats().resets;
    }
    stats_.record(f, data::msSince(f.acquired_at));
    counters.features = static_cast<int>(f.features.size());
    counters.sequence_ns = data::secToNs(f.sequence_s);
    ++counters.frames_processed;
    if (view) {
      f.imu.clear();
      if (!live) {
        if (!view->push(std::move(f))) break;
      } else if (!view->tryPush(f)) {
        if (view->closed()) break;
        ++stats_.view_frames_skipped;
      }
    }
  }
  if (biases) biases->close();
  if (view) view->close();
  if (writer_) writer_->close();
}

}  // namespace adugs::app
