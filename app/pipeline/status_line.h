#pragma once
// The one-line status the pipeline prints on stderr once a second (headless runs, and beside the
// window), e.g.
//   live: 12.3 s | 30.0 fps in, 29.4 fps out, 3 dropped | 148 features | tracking, 0 resets
#include <cstddef>
#include <string>

namespace adugs::app {

struct StatusFigures {
  double sequence_s = 0;         // of the last frame processed
  double fps_in = 0, fps_out = 0;  // frames acquired / processed per wall second, since the last line
  size_t dropped = 0;            // frames dropped by the live policy so far
  int features = 0;              // in the last frame processed
  bool estimating = false, initialized = false;
  int resets = 0;
};

std::string formatStatusLine(const std::string& prefix, const StatusFigures& s);

}  // namespace adugs::app
