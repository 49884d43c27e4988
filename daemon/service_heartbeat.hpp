// What systemd hears about the pipeline's health: READY=1 once the first frame is
// through, WATCHDOG=1 only while the processing loop keeps finishing frames. A stalled
// camera or a hung processing loop therefore lets the watchdog fire.
#pragma once

#include <cstdint>

#include "daemon/sd_notifier.hpp"

namespace ccdlane {

// Driven by the main loop's tick, not by the processing thread: a notification is a
// datagram send that blocks while systemd's queue is full, and a real-time thread must
// never wait for systemd. The processing loop's progress (its frame count) is what
// decides whether there is anything to vouch for.
class ServiceHeartbeat {
 public:
  explicit ServiceHeartbeat(SystemdNotifier& notifier) : notifier_(notifier) {}

  // `ready`: the first frame was processed; `frames_processed`: the loop's count so far.
  void tick(std::int64_t now_ns, bool ready, std::uint64_t frames_processed);

  bool ready_sent() const { return ready_sent_; }
  // How often to tick for this watchdog period: a third of it, at most 100 ms.
  std::int64_t tick_period_ns() const;

 private:
  SystemdNotifier& notifier_;
  bool ready_sent_ = false;
  std::uint64_t processed_at_last_ping_ = 0;
};

}  // namespace ccdlane
