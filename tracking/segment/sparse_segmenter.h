#pragma once
// A slow box segmenter (MobileSAM's encoder costs seconds per frame on a CPU) run sparsely: every
// `refresh_every` frames, or at once when a track appears or its box changes shape, the inner
// segmenter segments all tracked boxes of that frame; in between, each track's last mask is
// carried along by its tracked box (scaled and moved with it). A track without a mask yet gets
// its filled box - for the VIO, masking too much is the safe error. Asynchronous mode runs the
// inner segmenter on a worker thread so frames never wait for it (live use; results then depend
// on timing); synchronous mode runs it inline when due (reproducible, for measurements).
#include <condition_variable>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "tracking/segment/box_segmenter.h"
#include "tracking/sort/sort_tracker.h"

namespace adugs::tracking {

struct SparseSegmenterOptions {
  int refresh_every = 10;       // frames between inner runs while objects are present
  double reshape_ratio = 0.25;  // re-run when a box's aspect ratio moved this far (relative) from its mask's
  bool asynchronous = true;
};

class SparseSegmenter {
 public:
  SparseSegmenter(std::unique_ptr<BoxSegmenter> inner, const SparseSegmenterOptions& options);
  ~SparseSegmenter();  // waits for a run in flight
  // image: CV_8UC1 or CV_8UC3; objects with ids. Returns CV_8UC1 of the image size (255 = object).
  // Rethrows what the inner segmenter threw on the worker.
  cv::Mat segment(const cv::Mat& image, const std::vector<TrackedObject>& objects);
  int innerRuns() const { return runs_; }
  const BoxSegmenter& inner() const { return *inner_; }

 private:
  struct Entry {
    Box box;       // the tracked box the mask was computed for
    cv::Rect rect; // its clipped pixel rectangle
    cv::Mat mask;  // CV_8UC1 of rect's size
  };
  using Entries = std::map<int64_t, Entry>;
  Entries run(const cv::Mat& image, const std::vector<TrackedObject>& objects);
  bool due(const std::vector<TrackedObject>& objects) const;
  void work();

  std::unique_ptr<BoxSegmenter> inner_;
  SparseSegmenterOptions options_;
  Entries cache_;
  int frames_since_run_ = 0;
  int runs_ = 0;
  // Worker hand-over.
  std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<std::pair<cv::Mat, std::vector<TrackedObject>>> job_;
  std::optional<Entries> result_;
  std::exception_ptr error_;
  bool busy_ = false, stop_ = false;
  std::thread worker_;
};

}  // namespace adugs::tracking
