#pragma once
// The one pipeline of `adugs run` (recorded sequences) and `adugs live` (cameras, videos, paced
// replays): a source in; poses, statistics and the view out. Each stage on a thread of its own,
// joined by bounded queues (doc/architecture.md, "Data flow"):
//
//   source -> acquisition -> FrameGate -> detection -> masking -> front-end -> estimator -> [view]
//                                                         ^            ^            |
//                                                         +- gyro bias after frame k-3 / k-2
//                                                            (EstimatorFeedback)
//
// Playback (a source that is not live): the gate waits, nothing is dropped, and the output is the
// same to the byte whatever the threads' timing. Live: the gate drops the oldest waiting frame
// when the stages behind fall behind (counted), never an IMU sample.
//
// Stopping: at the end of the source; on SIGINT/SIGTERM (StopSignal), on requestStop() or when
// the user quits the window, the source is stopped and the frames already inside go through, so
// the trajectory and statistics are complete; on an error in any stage everything stops, and the
// error is handed back in the result after the poses already estimated were written.
#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "app/pipeline/estimator_feedback.h"
#include "app/pipeline/channel.h"
#include "app/pipeline/frame_gate.h"
#include "app/pipeline/masking_stage.h"
#include "app/pipeline/pipeline_stats.h"
#include "app/pipeline/stop_signal.h"
#include "app/pipeline/view_stage.h"
#include "data/formats/euroc_sensor_yaml.h"
#include "data/sources/sequence_source.h"
#include "vio/estimator/estimator_options.h"
#include "vio/frontend/feature_tracker_options.h"
#include "vio/imu/imu_preintegration.h"

namespace adugs::vio {
class SlidingWindowEstimator;
}  // namespace adugs::vio

namespace adugs::app {

class AcquisitionStage;
class DetectionStage;
class EstimatorStage;
class FrontEndStage;

struct PipelineOptions {
  MaskingOptions masking;
  vio::FeatureTrackerOptions tracker;
  bool estimate = true;  // false: vision only (a source without IMU): masking and tracking
  vio::EstimatorOptions estimator;
  vio::ImuPreintegrationOptions imu;
  std::string trajectory_path;  // TUM poses, flushed per pose (with an estimator)
  ViewOptions view;             // used when it asks for a video or a window
  size_t frame_queue = 2;       // frames that may wait at the entrance (live: then the oldest is dropped)
  double test_estimator_delay_ms = 0;  // tests only: a sleep per frame in the estimator stage
  std::string status_prefix = "run";   // the status line: "PREFIX: ..." once a second on stderr
  bool status = true;
};

struct PipelineResult {
  enum class End { kEndOfSource, kStopped, kError };
  End end = End::kEndOfSource;
  // kStopped: "SIGINT", "SIGTERM", "quit in the window", ...; kError: the message; kEndOfSource:
  // the source's stopReason() (a camera unplugged or stalled), "" at the end of a recording.
  std::string why;
  std::exception_ptr error;
  bool live = false;
  int threads = 0;
  size_t frames_acquired = 0, imu_acquired = 0;
  size_t frames_dropped = 0;        // by the live policy
  size_t imu_after_last_frame = 0;  // came after the last frame: no frame carried them
  data::SourceCounts source_counts;
  int64_t first_t_ns = -1;
  double wall_s = 0;
  // CPU time (user + system) of the run, all threads (OpenCV's and libtorch's workers included),
  // and of each stage's own thread (work a stage hands to library worker threads is not in it).
  double cpu_s = 0;
  std::vector<std::pair<std::string, double>> stage_cpu_s;
};

std::string toString(PipelineResult::End end);  // end_of_source | stopped | error

class Pipeline {
 public:
  // Builds every stage (loads the models: errors name the files). Ctrl-C is caught from here on.
  Pipeline(data::SequenceSource& source, const data::CameraCalibration& camera, const PipelineOptions& options);
  ~Pipeline();

  // Runs to the end (see above). Stage errors are returned in the result, not thrown.
  PipelineResult run();
  // Thread-safe: stop reading the source and let the frames inside finish.
  void requestStop(const std::string& why);

  const PipelineStats& stats() const;                    // after run()
  const vio::SlidingWindowEstimator* estimator() const;  // nullptr: vision only

 private:
  void fail(std::exception_ptr error);
  void printStatus(double interval_s);

  data::SequenceSource& source_;
  PipelineOptions options_;
  StopSignal stop_signal_;  // first: Ctrl-C while the models load stops the run at its start
  bool live_;
  FrameGate gate_;
  Channel<PipelineFrame> detected_, masked_, tracked_, viewed_;
  EstimatorFeedback biases_;
  PipelineCounters counters_;
  std::unique_ptr<AcquisitionStage> acquisition_;
  std::unique_ptr<DetectionStage> detection_;
  std::unique_ptr<MaskingStage> masking_;
  std::unique_ptr<FrontEndStage> front_end_;
  std::unique_ptr<EstimatorStage> estimator_;
  std::unique_ptr<ViewStage> view_;

  std::atomic<bool> stop_{false};
  std::atomic<int> running_{0};
  std::mutex mutex_;  // guards the fields below
  PipelineResult::End end_ = PipelineResult::End::kEndOfSource;
  std::string why_;
  std::exception_ptr error_;
  std::vector<std::pair<std::string, double>> stage_cpu_s_;
  size_t last_in_ = 0, last_out_ = 0;  // for the status line's rates
};

}  // namespace adugs::app
