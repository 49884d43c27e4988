// systemd service notifications (sd_notify): READY, WATCHDOG, STATUS, STOPPING. Without
// systemd (NOTIFY_SOCKET unset) every call is a cheap no-op. A send blocks while the
// receiver's queue is full: never call this from a real-time thread.
#pragma once

#include <atomic>
#include <cstdint>

namespace ccdlane {

class SystemdNotifier {
 public:
  // Reads NOTIFY_SOCKET / WATCHDOG_USEC / WATCHDOG_PID from the environment once.
  SystemdNotifier();

  bool enabled() const { return enabled_; }
  // The watchdog period systemd asked for (WatchdogSec=), 0 when none.
  std::int64_t watchdog_interval_us() const { return watchdog_us_; }

  void ready();
  void stopping();
  // STATUS=<line>: a one-line health summary (at most 200 characters are sent).
  void status(const char* line);
  // WATCHDOG=1, at most every third of the watchdog period (now_ns: CLOCK_MONOTONIC).
  // Returns true when a ping was sent.
  bool watchdog_kick(std::int64_t now_ns);

  std::uint64_t watchdog_pings() const { return pings_.load(std::memory_order_relaxed); }

 private:
  void send(const char* message);

  bool enabled_ = false;
  std::int64_t watchdog_us_ = 0;
  std::int64_t last_kick_ns_ = 0;
  std::atomic<std::uint64_t> pings_{0};
  std::atomic<bool> failure_reported_{false};
};

}  // namespace ccdlane
