#pragma once
// The pipeline's view, on a thread of its own after the estimator: each frame drawn as the paper's
// Fig. 1/3 view (app/pipeline/overlay_video.h: dynamic mask tinted, boxes with ids, features kept
// green and dropped-as-dynamic red, a status line), with the top view of the trajectory beside it
// when an estimator runs (app/pipeline/top_view.h); written to a video file and/or shown in a
// window (app/pipeline/live_window.h).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/pipeline/channel.h"
#include "app/pipeline/pipeline_frame.h"

namespace adugs::app {

class LiveWindow;
class OverlayVideo;

struct ViewOptions {
  std::string overlay_path;  // video (.avi / .mp4) of every frame; "" = none
  double fps = 20;           // of the video
  bool window = false;       // show a window (LiveWindow::available() must hold)
  bool top_view = false;     // an estimator runs: draw the trajectory beside the frame
  std::string title = "adugs";
};

class ViewStage {
 public:
  explicit ViewStage(const ViewOptions& options);  // throws InputError for a bad video name
  ~ViewStage();

  // Until `in` is drained. on_quit: called once when the user quits the window.
  void run(Channel<PipelineFrame>& in, const std::function<void()>& on_quit);

  // The frame as the view draws it (BGR).
  cv::Mat draw(const PipelineFrame& frame);

 private:
  ViewOptions options_;
  std::unique_ptr<OverlayVideo> video_;
  std::unique_ptr<LiveWindow> window_;
  std::vector<data::StampedPose> trail_;
};

}  // namespace adugs::app
