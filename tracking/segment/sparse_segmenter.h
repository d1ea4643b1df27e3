#pragma once
// A box segmenter run sparsely: a track's mask is computed when the track appears, when its box
// changes shape, and every `refresh_every` frames; in between, the track's last mask is carried
// along by its tracked box (scaled and moved with it). A track without a mask yet gets its filled
// box - for the VIO, masking too much is the safe error.
// A slow segmenter (BoxSegmenter::slow(): MobileSAM, whose image encoder costs seconds per frame on
// a CPU and is shared by every box) segments all tracked boxes of a frame whenever one is due; a
// per-box one (GrabCut) segments only the boxes that are due, so each frame pays for about
// 1 / refresh_every of its boxes. Asynchronous mode runs the inner segmenter on a worker thread so
// frames never wait for it (live use; results then depend on timing); synchronous mode runs it
// inline when due (reproducible, for measurements).
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

// The objects' pixels, the motion cue's boxes (class kMovingClass) cut with the point prompts and
// the others without: in a detector's box a point that looks still may be on an object moving
// along its epipolar line (tracking/object_motion.h).
cv::Mat segmentObjects(BoxSegmenter& segmenter, const cv::Mat& image, const std::vector<TrackedObject>& objects,
                       const std::vector<PointPrompt>& points);

class SparseSegmenter {
 public:
  SparseSegmenter(std::unique_ptr<BoxSegmenter> inner, const SparseSegmenterOptions& options);
  ~SparseSegmenter();  // waits for a run in flight
  // image: CV_8UC1 or CV_8UC3; objects with ids; points: prompts for the motion cue's boxes
  // (segmentObjects). Returns CV_8UC1 of the image size (255 = object). Rethrows what the inner
  // segmenter threw on the worker.
  cv::Mat segment(const cv::Mat& image, const std::vector<TrackedObject>& objects,
                  const std::vector<PointPrompt>& points = {});
  int innerRuns() const { return runs_; }
  int64_t boxesSegmented() const { return boxes_segmented_; }  // by the inner segmenter, over all runs
  const BoxSegmenter& inner() const { return *inner_; }

 private:
  struct Entry {
    Box box;       // the tracked box the mask was computed for
    cv::Rect rect; // its clipped pixel rectangle
    cv::Mat mask;  // CV_8UC1 of rect's size
    int age = 0;   // frames since it was computed
  };
  using Entries = std::map<int64_t, Entry>;
  Entries run(const cv::Mat& image, const std::vector<TrackedObject>& objects, const std::vector<PointPrompt>& points);
  bool due(const TrackedObject& object) const;
  // The objects to segment in this frame (all or none for a slow segmenter).
  std::vector<TrackedObject> toSegment(const std::vector<TrackedObject>& objects) const;
  void work();

  std::unique_ptr<BoxSegmenter> inner_;
  SparseSegmenterOptions options_;
  Entries cache_;
  int runs_ = 0;
  int64_t boxes_segmented_ = 0;
  // Worker hand-over.
  std::mutex mutex_;
  std::condition_variable wake_;
  struct Job {
    cv::Mat image;
    std::vector<TrackedObject> objects;
    std::vector<PointPrompt> points;
  };
  std::optional<Job> job_;
  std::optional<Entries> result_;
  std::exception_ptr error_;
  bool busy_ = false, stop_ = false;
  std::thread worker_;
};

}  // namespace adugs::tracking
