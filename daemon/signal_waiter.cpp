// sigtimedwait keeps signal handling in ordinary code: no async-signal-safety rules,
// no flag polling, and the status tick and the signal wait are one call.
#include "daemon/signal_waiter.hpp"

#include <pthread.h>

#include <cerrno>
#include <ctime>

namespace ccdlane {

SignalWaiter::SignalWaiter() {
  sigemptyset(&set_);
  sigaddset(&set_, SIGTERM);
  sigaddset(&set_, SIGINT);
  sigaddset(&set_, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &set_, &previous_);
  signal(SIGPIPE, SIG_IGN);
}

SignalWaiter::~SignalWaiter() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

SignalWaiter::Event SignalWaiter::wait(std::int64_t timeout_ns) {
  if (timeout_ns < 0) timeout_ns = 0;
  timespec timeout{};
  timeout.tv_sec = static_cast<time_t>(timeout_ns / 1'000'000'000);
  timeout.tv_nsec = static_cast<long>(timeout_ns % 1'000'000'000);
  int sig = -1;
  do {
    sig = sigtimedwait(&set_, nullptr, &timeout);
  } while (sig < 0 && errno == EINTR);
  if (sig < 0) return Event::none;
  last_ = sig;
  return sig == SIGHUP ? Event::hangup : Event::terminate;
}

bool SignalWaiter::terminate_pending() const {
  sigset_t pending;
  sigemptyset(&pending);
  if (sigpending(&pending) != 0) return false;
  return sigismember(&pending, SIGTERM) == 1 || sigismember(&pending, SIGINT) == 1;
}

}  // namespace ccdlane
