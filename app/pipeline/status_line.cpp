#include "app/pipeline/status_line.h"

#include <cstdio>

namespace adugs::app {

std::string formatStatusLine(const std::string& prefix, const StatusFigures& s) {
  char line[256];
  const char* state = !s.estimating ? "vision only" : s.initialized ? "tracking" : "initialising";
  std::snprintf(line, sizeof line, "%s: %.1f s | %.1f fps in, %.1f fps out, %zu dropped | %d features | %s, %d resets",
                prefix.c_str(), s.sequence_s, s.fps_in, s.fps_out, s.dropped, s.features, state, s.resets);
  return line;
}

}  // namespace adugs::app
