#pragma once
// The pipeline's entrance: the acquisition thread puts in IMU samples and frames as the source
// gives them; the first stage takes out PipelineFrames, each carrying every IMU sample since the
// previous frame taken out.
//
// The declared policy when the stages behind it fall behind (`capacity` frames already wait):
//   kWait        (playback) the acquisition waits: nothing is lost, runs are reproducible;
//   kDropOldest  (live sources, which cannot be paused) the oldest waiting frame is dropped and
//                counted; its IMU samples go with the frame after it. IMU samples are never
//                dropped, and the stages always get the freshest frames.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <vector>

#include "app/pipeline/pipeline_frame.h"

namespace adugs::app {

class FrameGate {
 public:
  enum class Policy { kWait, kDropOldest };
  FrameGate(size_t capacity, Policy policy);

  void addImu(const data::ImuSample& sample);
  // False once the gate is closed (the frame is not taken).
  bool addFrame(data::Frame frame, double sequence_s, std::chrono::steady_clock::time_point acquired_at);
  // The next frame, its index counted over the frames taken out; false once closed and empty.
  bool pop(PipelineFrame* out);
  // No more input: pop() drains what waits, addFrame() refuses.
  void close();

  size_t framesDropped() const;
  // IMU samples no frame will carry (after the last frame that came in).
  size_t imuPending() const;

 private:
  const size_t capacity_;
  const Policy policy_;
  mutable std::mutex mutex_;
  std::condition_variable not_empty_, not_full_;
  std::deque<PipelineFrame> waiting_;
  std::vector<data::ImuSample> pending_imu_;  // since the last frame that came in
  int next_index_ = 0;
  size_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace adugs::app
