// libsystemd's sd_notify does the protocol (a datagram to $NOTIFY_SOCKET, abstract
// socket names included); this adds rate limiting and a once-only failure report.
#include "daemon/sd_notifier.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <systemd/sd-daemon.h>

#include "base/log.hpp"

namespace ccdlane {

SystemdNotifier::SystemdNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  enabled_ = socket != nullptr && socket[0] != '\0';
  std::uint64_t usec = 0;
  // > 0 only when WATCHDOG_USEC is set and WATCHDOG_PID (if set) is this process.
  if (sd_watchdog_enabled(0, &usec) > 0) watchdog_us_ = static_cast<std::int64_t>(usec);
}

void SystemdNotifier::send(const char* message) {
  if (!enabled_) return;
  const int r = sd_notify(0, message);
  if (r < 0 && first_time(failure_reported_))
    log_line(LogLevel::warning, "systemd", "sd_notify to $NOTIFY_SOCKET failed: %s (further failures not logged)",
             std::strerror(-r));
}

void SystemdNotifier::ready() { send("READY=1"); }
void SystemdNotifier::stopping() { send("STOPPING=1"); }

void SystemdNotifier::status(const char* line) {
  if (!enabled_) return;
  char message[224];
  std::snprintf(message, sizeof message, "STATUS=%.200s", line);
  send(message);
}

bool SystemdNotifier::watchdog_kick(std::int64_t now_ns) {
  if (watchdog_us_ <= 0) return false;
  if (last_kick_ns_ != 0 && now_ns - last_kick_ns_ < watchdog_us_ * 1000 / 3) return false;
  last_kick_ns_ = now_ns;
  send("WATCHDOG=1");
  pings_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

}  // namespace ccdlane
