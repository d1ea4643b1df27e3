#include "app/pipeline/stop_signal.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <stdexcept>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

namespace adugs::app {
namespace {

int g_pipe[2] = {-1, -1};
volatile std::sig_atomic_t g_signal = 0;
std::atomic<bool> g_installed{false};
struct sigaction g_previous_int, g_previous_term;

void onSignal(int sig) {
  if (g_signal != 0) {  // the second one: the default action, now
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_signal = sig;
  const int saved = errno;
  const char byte = 's';
  [[maybe_unused]] const ssize_t n = ::write(g_pipe[1], &byte, 1);
  errno = saved;
}

}  // namespace

StopSignal::StopSignal() {
  if (g_installed.exchange(true)) throw std::logic_error("StopSignal: only one at a time");
  if (::pipe2(g_pipe, O_CLOEXEC | O_NONBLOCK) != 0) {
    g_installed = false;
    throw std::runtime_error("StopSignal: cannot create a pipe");
  }
  g_signal = 0;
  struct sigaction action = {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
}

StopSignal::~StopSignal() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
  ::close(g_pipe[0]);
  ::close(g_pipe[1]);
  g_pipe[0] = g_pipe[1] = -1;
  g_installed = false;
}

bool StopSignal::wait(std::chrono::milliseconds timeout) {
  if (g_signal != 0 && !reported_) return reported_ = true;
  pollfd p = {g_pipe[0], POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(timeout.count())) > 0) {
    char buffer[64];
    while (::read(g_pipe[0], buffer, sizeof buffer) > 0) {
    }
  }
  if (g_signal != 0 && !reported_) return reported_ = true;
  return false;
}

void StopSignal::wake() {
  const char byte = 'w';
  [[maybe_unused]] const ssize_t n = ::write(g_pipe[1], &byte, 1);
}

int StopSignal::signalNumber() const { return g_signal; }

}  // namespace adugs::app
