// A ping needs progress since the previous ping, not just "some frame ever": that is
// what turns a stall into a missed watchdog.
#include "daemon/service_heartbeat.hpp"

#include <algorithm>

namespace ccdlane {

void ServiceHeartbeat::tick(std::int64_t now_ns, bool ready, std::uint64_t frames_processed) {
  if (!ready) return;
  if (!ready_sent_) {
    notifier_.ready();
    ready_sent_ = true;
  }
  if (frames_processed != processed_at_last_ping_ && notifier_.watchdog_kick(now_ns))
    processed_at_last_ping_ = frames_processed;
}

std::int64_t ServiceHeartbeat::tick_period_ns() const {
  constexpr std::int64_t kMax = 100'000'000;
  const std::int64_t watchdog_ns = notifier_.watchdog_interval_us() * 1000;
  return watchdog_ns > 0 ? std::clamp(watchdog_ns / 3, std::int64_t{1'000'000}, kMax) : kMax;
}

}  // namespace ccdlane
