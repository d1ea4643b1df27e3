#include "app/pipeline/view_stage.h"

#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "app/pipeline/live_window.h"
#include "app/pipeline/overlay_video.h"
#include "app/pipeline/top_view.h"

namespace adugs::app {

ViewStage::ViewStage(const ViewOptions& options) : options_(options) {
  if (!options_.overlay_path.empty()) video_ = std::make_unique<OverlayVideo>(options_.overlay_path, options_.fps);
  if (options_.window) window_ = std::make_unique<LiveWindow>(options_.title);
}

ViewStage::~ViewStage() = default;

cv::Mat ViewStage::draw(const PipelineFrame& f) {
  OverlayContent c;
  c.mask = f.mask;
  c.objects = f.objects;
  c.kept = f.features.pixels;
  c.dropped = f.dropped_points;
  const double masked =
      f.mask.empty() ? 0.0 : static_cast<double>(cv::countNonZero(f.mask)) / static_cast<double>(f.mask.total());
  char status[160];
  std::snprintf(status, sizeof status, "t %.2f s | features %zu kept, %d dropped as dynamic | masked %.1f %% | %zu objects",
                f.sequence_s, f.features.size(), f.dropped_dynamic, 100.0 * masked, f.objects.size());
  c.status = status;
  const cv::Mat overlay = drawOverlay(f.frame.colour.empty() ? f.frame.image : f.frame.colour, c);
  if (!options_.top_view) return overlay;
  if (f.pose) trail_.push_back(*f.pose);
  const cv::Mat panel = drawTopView(trail_, {overlay.rows, overlay.rows}, f.pose ? "tracking" : "initialising");
  cv::Mat both;
  cv::hconcat(overlay, panel, both);
  return both;
}

void ViewStage::run(Channel<PipelineFrame>& in, const std::function<void()>& on_quit) {
  PipelineFrame f;
  bool quit = false;
  while (in.pop(&f)) {
    const cv::Mat view = draw(f);
    if (video_) video_->write(view);
    if (window_ && !quit && !window_->show(view)) {
      quit = true;
      if (on_quit) on_quit();
    }
  }
}

}  // namespace adugs::app
