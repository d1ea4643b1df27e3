#pragma once
// Ctrl-C for the pipeline: while a StopSignal exists, SIGINT and SIGTERM do not end the process
// but are turned into a stop request that wait() reports (a self-pipe: the handler only writes one
// byte, whatever thread the kernel picked). A second signal ends the process at once, with the
// signal's default action, for a run that does not stop. The destructor puts back the previous
// handlers. One StopSignal at a time.
#include <chrono>

namespace adugs::app {

class StopSignal {
 public:
  StopSignal();
  ~StopSignal();
  StopSignal(const StopSignal&) = delete;
  StopSignal& operator=(const StopSignal&) = delete;

  // Waits up to `timeout` for a signal or a wake(); true once, for the first signal (also when it
  // arrived before the call).
  bool wait(std::chrono::milliseconds timeout);
  // Ends a wait() early from another thread (e.g. the pipeline finished).
  void wake();
  // The signal that arrived (SIGINT, SIGTERM), 0 if none.
  int signalNumber() const;

 private:
  bool reported_ = false;
};

}  // namespace adugs::app
