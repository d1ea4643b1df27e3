#include "app/pipeline/live_window.h"

#include <cstdlib>
#include <stdexcept>

#include <visp3/core/vpConfig.h>
#include <visp3/core/vpDisplay.h>
#include <visp3/core/vpException.h>
#include <visp3/core/vpImage.h>
#include <visp3/core/vpImageConvert.h>
#ifdef VISP_HAVE_X11
#include <X11/Xlib.h>
#include <visp3/gui/vpDisplayX.h>
#endif

namespace adugs::app {

struct LiveWindow::Impl {
  vpImage<vpRGBa> image;
#ifdef VISP_HAVE_X11
  std::unique_ptr<vpDisplayX> display;
#endif
};

LiveWindow::LiveWindow(const std::string& title) : impl_(std::make_unique<Impl>()), title_(title) {}

LiveWindow::~LiveWindow() = default;

bool LiveWindow::available(std::string* why) {
  const auto no = [&](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
#ifdef VISP_HAVE_X11
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || name[0] == '\0') return no("$DISPLAY is not set");
  Display* display = XOpenDisplay(nullptr);
  if (display == nullptr) return no(std::string("cannot connect to the X server of DISPLAY=") + name);
  XCloseDisplay(display);
  return true;
#else
  return no("this ViSP has no X11 display");
#endif
}

bool LiveWindow::show(const cv::Mat& bgr) {
#ifdef VISP_HAVE_X11
  const bool resized = bgr.rows != static_cast<int>(impl_->image.getHeight()) ||
                       bgr.cols != static_cast<int>(impl_->image.getWidth());
  vpImageConvert::convert(bgr, impl_->image);
  if (!impl_->display || resized) {
    impl_->display.reset();
    try {
      impl_->display = std::make_unique<vpDisplayX>();
      impl_->display->init(impl_->image, -1, -1, title_);
    } catch (const vpException& e) {
      const char* name = std::getenv("DISPLAY");
      throw std::runtime_error(std::string("the live window cannot open on DISPLAY=") + (name ? name : "") + " (" +
                               e.getMessage() + "); run with --no-window");
    }
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
