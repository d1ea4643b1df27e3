#pragma once
// A live source that ended by itself (a camera unplugged, a stream that stalled) ends `adugs live`
// and `adugs record` with every output written, then with exit code kExitSourceLost: a script can
// tell such a run from one the user stopped (0) or one that failed on bad input (2).
#include <stdexcept>

namespace adugs::app {

constexpr int kExitSourceLost = 4;

class SourceLost : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace adugs::app
