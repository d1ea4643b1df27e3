#pragma once
// The live view's window: ViSP's X11 display (vpDisplayX), opened on the first image (check
// available() first). The user ends the run with `q` or Escape in the window.
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace adugs::app {

class LiveWindow {
 public:
  explicit LiveWindow(const std::string& title);
  ~LiveWindow();
  // Shows a BGR image (the window follows its size); false once the user asked to quit.
  bool show(const cv::Mat& bgr);

  // Whether a window can be opened here: ViSP built with X11, $DISPLAY set and its X server
  // answering. When not, *why says why (if given).
  static bool available(std::string* why = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string title_;
};

}  // namespace adugs::app
