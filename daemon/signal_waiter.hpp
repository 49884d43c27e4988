// SIGTERM, SIGINT and SIGHUP as events of the main loop (sigtimedwait), not handlers:
// blocked in every thread, so they reach only the one that waits for them.
#pragma once

#include <signal.h>

#include <cstdint>

namespace ccdlane {

class SignalWaiter {
 public:
  enum class Event { none, terminate, hangup };

  // Blocks the three signals in the calling thread; threads created afterwards inherit
  // that. Construct before any thread exists. Also ignores SIGPIPE.
  SignalWaiter();
  ~SignalWaiter();  // restores the previous mask
  SignalWaiter(const SignalWaiter&) = delete;
  SignalWaiter& operator=(const SignalWaiter&) = delete;

  // Waits up to timeout_ns for one of them; none on timeout.
  Event wait(std::int64_t timeout_ns);
  // Whether SIGTERM or SIGINT is waiting, without taking it: start-up work that takes
  // seconds (rendering the synthetic drive) asks this between steps.
  bool terminate_pending() const;
  // The signal behind the last event (SIGTERM, SIGINT, SIGHUP).
  int last_signal() const { return last_; }

 private:
  sigset_t set_{};
  sigset_t previous_{};
  int last_ = 0;
};

}  // namespace ccdlane
