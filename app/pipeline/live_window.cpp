#include "app/pipeline/live_window.h"

#include <cstdlib>
#include <stdexcept>

#include <visp3/core/vpConfig.h>
#include <visp3/core/vpDisplay.h>
#include <visp3/core/vpImage.h>
#include <visp3/core/vpImageConvert.h>
#ifdef VISP_HAVE_X11
#include <visp3/gui/vpDisplayX.h>
#endif

namespace adugs::app {

struct LiveWindow::Impl {
  vpImage<vpRGBa> image;
#ifdef VISP_HAVE_X11
  std::unique_ptr<vpDisplayX> display;
#endif
};

LiveWindow::LiveWindow(const std::string& title) : impl_(std::make_unique<Impl>()), title_(title) {
  if (!available()) throw std::runtime_error("no window: ViSP has no X11 display or $DISPLAY is not set");
}

LiveWindow::~LiveWindow() = default;

bool LiveWindow::available() {
#ifdef VISP_HAVE_X11
  const char* display = std::getenv("DISPLAY");
  return display != nullptr && display[0] != '\0';
#else
  return false;
#endif
}

bool LiveWindow::show(const cv::Mat& bgr) {
#ifdef VISP_HAVE_X11
  const bool resized = bgr.rows != static_cast<int>(impl_->image.getHeight()) ||
                       bgr.cols != static_cast<int>(impl_->image.getWidth());
  vpImageConvert::convert(bgr, impl_->image);
  if (!impl_->display || resized) {
    impl_->display.reset();
    impl_->display = std::make_unique<vpDisplayX>();
    impl_->display->init(impl_->image, -1, -1, title_);
  }
  vpDisplay::display(impl_->image);
  vpDisplay::flush(impl_->image);
  std::string key;
  if (vpDisplay::getKeyboardEvent(impl_->image, key, false) && (key == "q" || key == "Q" || key == "\x1b"))
    return false;
  return true;
#else
  (void)bgr;
  return false;
#endif
}

}  // namespace adugs::app
