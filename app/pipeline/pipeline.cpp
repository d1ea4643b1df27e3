#include "app/pipeline/pipeline.h"

#include <chrono>
#include <csignal>
#include <functional>
#include <iostream>
#include <thread>
#include <vector>

#include <sys/resource.h>
#include <time.h>

#include "app/pipeline/acquisition_stage.h"
#include "app/pipeline/detection_stage.h"
#include "app/pipeline/estimator_stage.h"
#include "app/pipeline/frontend_stage.h"
#include "app/pipeline/status_line.h"
#include "data/camera_model.h"
#include "vio/estimator/sliding_window_estimator.h"

namespace adugs::app {

namespace {

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double processCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace

std::string toString(PipelineResult::End end) {
  switch (end) {
    case PipelineResult::End::kEndOfSource: return "end_of_source";
    case PipelineResult::End::kStopped: return "stopped";
    case PipelineResult::End::kError: return "error";
  }
  return "?";
}

Pipeline::Pipeline(data::SequenceSource& source, const data::CameraCalibration& camera,
                   const PipelineOptions& options)
    : source_(source),
      options_(options),
      live_(source.isLive()),
      gate_(options.frame_queue, live_ ? FrameGate::Policy::kDropOldest : FrameGate::Policy::kWait),
      detected_(2),
      masked_(2),
      tracked_(2),
      viewed_(4) {
  const data::CameraModel model(camera);
  acquisition_ = std::make_unique<AcquisitionStage>(source_);
  masking_ = std::make_unique<MaskingStage>(options_.masking, model, camera.T_B_C);
  detection_ = std::make_unique<DetectionStage>(options_.masking.source == MaskSource::kDetector ? options_.masking.detector_model : "",
                                                options_.masking.detector_config, options_.masking.masker.detect_every);
  front_end_ = std::make_unique<FrontEndStage>(options_.tracker, model, camera.T_B_C);
  std::unique_ptr<vio::SlidingWindowEstimator> estimator;
  if (options_.estimate)
    estimator = std::make_unique<vio::SlidingWindowEstimator>(options_.estimator, model.centreFocalPx(),
                                                              camera.T_B_C, options_.imu);
  estimator_ = std::make_unique<EstimatorStage>(std::move(estimator), options_.trajectory_path,
                                                options_.test_estimator_delay_ms);
  if (!options_.view.overlay_path.empty() || options_.view.window) {
    ViewOptions view = options_.view;
    view.top_view = options_.estimate;
    view_ = std::make_unique<ViewStage>(view);
  }
}

Pipeline::~Pipeline() = default;

const PipelineStats& Pipeline::stats() const { return estimator_->stats(); }
const vio::SlidingWindowEstimator* Pipeline::estimator() const { return estimator_->estimator(); }

void Pipeline::requestStop(const std::string& why) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_ || error_) return;
    end_ = PipelineResult::End::kStopped;
    why_ = why;
  }
  stop_ = true;
  source_.stop();
  gate_.close();  // the acquisition stops; what is inside goes on through
}

void Pipeline::fail(std::exception_ptr error) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_) return;
    error_ = error;
    end_ = PipelineResult::End::kError;
    try {
      std::rethrow_exception(error);
    } catch (const std::exception& e) {
      why_ = e.what();
    } catch (...) {
      why_ = "unknown error";
    }
  }
  // Everything stops at once.
  stop_ = true;
  source_.stop();
  gate_.close();
  detected_.close();
  masked_.close();
  tracked_.close();
  viewed_.close();
  biases_.close();
}

void Pipeline::printStatus(double interval_s) {
  StatusFigures s;
  const size_t in = counters_.frames_acquired, out = counters_.frames_processed;
  s.sequence_s = data::nsToSec(counters_.sequence_ns);
  s.fps_in = interval_s > 0 ? static_cast<double>(in - last_in_) / interval_s : 0;
  s.fps_out = interval_s > 0 ? static_cast<double>(out - last_out_) / interval_s : 0;
  last_in_ = in;
  last_out_ = out;
  s.dropped = gate_.framesDropped();
  s.features = counters_.features;
  s.estimating = options_.estimate;
  s.initialized = counters_.initialized;
  s.resets = counters_.resets;
  std::cerr << formatStatusLine(options_.status_prefix, s) << "\n" << std::flush;
}

PipelineResult Pipeline::run() {
  using Clock = std::chrono::steady_clock;
  const auto wall_start = Clock::now();
  const double cpu_start = processCpuSeconds();
  EstimatorFeedback* biases = options_.estimate ? &biases_ : nullptr;
  Channel<PipelineFrame>* view = view_ ? &viewed_ : nullptr;

  // The stages, named for the CPU figures; each slot is written only by its own thread.
  std::vector<std::pair<std::string, std::function<void()>>> stages = {
      {"acquisition", [&] { acquisition_->run(gate_, counters_, stop_); }},
      {"detection", [&] { detection_->run(gate_, detected_); }},
      {"masking", [&] { masking_->run(detected_, masked_, biases); }},
      {"front_end", [&] { front_end_->run(masked_, tracked_, biases); }},
      {"estimator", [&] { estimator_->run(tracked_, view, biases, counters_, live_); }}};
  if (view_) stages.emplace_back("view", [&] { view_->run(viewed_, [this] { requestStop("quit in the window"); }); });
  stage_cpu_s_.clear();
  for (const auto& stage : stages) stage_cpu_s_.emplace_back(stage.first, 0.0);
  running_ = static_cast<int>(stages.size());
  std::vector<std::thread> threads;
  for (size_t i = 0; i < stages.size(); ++i) {
    threads.emplace_back([this, i, body = stages[i].second] {
      try {
        body();
      } catch (...) {
        fail(std::current_exception());
      }
      stage_cpu_s_[i].second = threadCpuSeconds();
      --running_;
      stop_signal_.wake();
    });
  }

  // This thread watches: Ctrl-C, and the status line once a second.
  auto last_status = Clock::now();
  while (running_ > 0) {
    const auto next_status = last_status + std::chrono::seconds(1);
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next_status - Clock::now());
    if (stop_signal_.wait(std::max(wait, std::chrono::milliseconds(0))))
      requestStop(stop_signal_.signalNumber() == SIGTERM ? "SIGTERM" : "SIGINT");
    if (Clock::now() >= next_status) {
      if (options_.status && running_ > 0)
        printStatus(std::chrono::duration<double>(Clock::now() - last_status).count());
      last_status = Clock::now();
    }
  }
  for (std::thread& t : threads) t.join();

  PipelineResult r;
  r.end = end_;
  r.why = why_;
  // A live source that ended by itself (unplugged, stalled) says why.
  if (r.end == PipelineResult::End::kEndOfSource) r.why = source_.stopReason();
  r.error = error_;
  r.live = live_;
  r.threads = static_cast<int>(threads.size());
  r.frames_acquired = counters_.frames_acquired;
  r.imu_acquired = counters_.imu_acquired;
  r.frames_dropped = gate_.framesDropped();
  r.imu_after_last_frame = gate_.imuPending();
  r.source_counts = acquisition_->counts();
  r.first_t_ns = acquisition_->firstTimeNs();
  r.wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  r.cpu_s = processCpuSeconds() - cpu_start;
  r.stage_cpu_s = stage_cpu_s_;
  return r;
}

}  // namespace adugs::app
