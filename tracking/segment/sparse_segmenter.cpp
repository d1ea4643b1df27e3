#include "tracking/segment/sparse_segmenter.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "tracking/detect/motion_cue.h"

namespace adugs::tracking {
namespace {

// A cached mask moved and scaled from the box it was computed for to the current box, OR-ed into
// `mask` (clipped to the image).
void pasteCarried(const Box& old_box, const cv::Rect& old_rect, const cv::Mat& old_mask, const Box& box, cv::Mat& mask) {
  const double sx = box.w / std::max(old_box.w, 1e-6), sy = box.h / std::max(old_box.h, 1e-6);
  const cv::Size size(std::max(1, static_cast<int>(std::lround(old_rect.width * sx))),
                      std::max(1, static_cast<int>(std::lround(old_rect.height * sy))));
  const cv::Point tl(static_cast<int>(std::lround((old_rect.x - old_box.cx) * sx + box.cx)),
                     static_cast<int>(std::lround((old_rect.y - old_box.cy) * sy + box.cy)));
  const cv::Rect target = cv::Rect(tl, size) & cv::Rect(0, 0, mask.cols, mask.rows);
  if (target.empty()) return;
  cv::Mat scaled;
  cv::resize(old_mask, scaled, size, 0, 0, cv::INTER_NEAREST);
  cv::Mat dst = mask(target);
  cv::bitwise_or(dst, scaled(cv::Rect(target.tl() - tl, target.size())), dst);
}

double aspect(const Box& b) { return b.w / std::max(b.h, 1e-6); }

}  // namespace

cv::Mat segmentObjects(BoxSegmenter& segmenter, const cv::Mat& image, const std::vector<TrackedObject>& objects,
                       const std::vector<PointPrompt>& points) {
  std::vector<Box> boxes, cue_boxes;
  for (const TrackedObject& o : objects)
    (o.class_id == kMovingClass && !points.empty() ? cue_boxes : boxes).push_back(o.box);
  cv::Mat mask = segmenter.segment(image, boxes);
  if (!cue_boxes.empty()) mask |= segmenter.segmentWithPoints(image, cue_boxes, points);
  return mask;
}

SparseSegmenter::SparseSegmenter(std::unique_ptr<BoxSegmenter> inner, const SparseSegmenterOptions& options)
    : inner_(std::move(inner)), options_(options) {
  if (!inner_) throw std::invalid_argument("SparseSegmenter: no segmenter");
  if (options_.refresh_every < 1) throw std::invalid_argument("SparseSegmenter: refresh_every must be >= 1");
  if (options_.asynchronous) worker_ = std::thread([this] { work(); });
}

SparseSegmenter::~SparseSegmenter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

SparseSegmenter::Entries SparseSegmenter::run(const cv::Mat& image, const std::vector<TrackedObject>& objects,
                                              const std::vector<PointPrompt>& points) {
  // One call for all the boxes: a slow segmenter then runs its encoder once.
  const cv::Mat all = segmentObjects(*inner_, image, objects, points);
  Entries entries;
  for (const TrackedObject& o : objects) {
    const cv::Rect r = clippedRect(o.box, image.cols, image.rows);
    if (!r.empty()) entries[o.id] = {o.box, r, all(r).clone()};
  }
  return entries;
}

void SparseSegmenter::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || job_.has_value(); });
    if (stop_) return;
    auto job = std::move(*job_);
    job_.reset();
    lock.unlock();
    Entries entries;
    std::exception_ptr error;
    try {
      entries = run(job.image, job.objects, job.points);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    result_ = std::move(entries);
    error_ = error;
    busy_ = false;
  }
}

bool SparseSegmenter::due(const TrackedObject& o) const {
  const auto it = cache_.find(o.id);
  if (it == cache_.end()) return true;  // a new track
  if (std::abs(aspect(o.box) / aspect(it->second.box) - 1.0) > options_.reshape_ratio) return true;
  return it->second.age >= options_.refresh_every;
}

std::vector<TrackedObject> SparseSegmenter::toSegment(const std::vector<TrackedObject>& objects) const {
  std::vector<TrackedObject> due_now;
  for (const TrackedObject& o : objects)
    if (due(o)) due_now.push_back(o);
  // The shared encoder costs the same for one box as for all: then all are refreshed together.
  if (inner_->slow() && !due_now.empty()) return objects;
  return due_now;
}

cv::Mat SparseSegmenter::segment(const cv::Mat& image, const std::vector<TrackedObject>& objects,
                                 const std::vector<PointPrompt>& points) {
  for (auto& [id, entry] : cache_) ++entry.age;
  if (options_.asynchronous) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
    if (result_) {
      for (auto& [id, entry] : *result_) cache_[id] = std::move(entry);
      result_.reset();
    }
    if (!busy_) {
      std::vector<TrackedObject> due_now = toSegment(objects);
      if (!due_now.empty()) {
        job_.emplace(Job{image.clone(), std::move(due_now), points});
        busy_ = true;
        ++runs_;
        boxes_segmented_ += static_cast<int64_t>(job_->objects.size());
        wake_.notify_one();
      }
    }
  } else if (const std::vector<TrackedObject> due_now = toSegment(objects); !due_now.empty()) {
    for (auto& [id, entry] : run(image, due_now, points)) cache_[id] = std::move(entry);
    ++runs_;
    boxes_segmented_ += static_cast<int64_t>(due_now.size());
  }
  // Forget tracks that ended.
  for (auto it = cache_.begin(); it != cache_.end();) {
    bool alive = false;
    for (const TrackedObject& o : objects) alive |= o.id == it->first;
    it = alive ? std::next(it) : cache_.erase(it);
  }
  cv::Mat mask = cv::Mat::zeros(image.size(), CV_8UC1);
  for (const TrackedObject& o : objects) {
    const auto it = cache_.find(o.id);
    if (it != cache_.end()) {
      pasteCarried(it->second.box, it->second.rect, it->second.mask, o.box, mask);
    } else {
      const cv::Rect r = clippedRect(o.box, image.cols, image.rows);
      if (!r.empty()) mask(r).setTo(255);
    }
  }
  return mask;
}

}  // namespace adugs::tracking
