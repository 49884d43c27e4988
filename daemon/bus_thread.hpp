// ccdlaned's one LCM receiving path: a thread that handles the bus for every subscriber
// (the other-instance watch on the status channel, the vehicle state), so that vehicle
// messages are taken as they come, not once a second at the status tick.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>

#include <lcm/lcm.h>

namespace ccdlane {

class BusThread {
 public:
  // `lcm` is not owned and must outlive the thread. Subscribe before start(): LCM calls
  // the handlers on this thread, never two lcm_handle calls on one lcm_t at a time.
  explicit BusThread(lcm_t* lcm) : lcm_(lcm) {}
  ~BusThread() { stop(); }
  BusThread(const BusThread&) = delete;
  BusThread& operator=(const BusThread&) = delete;

  void start();
  // Joins within one handling timeout (kWaitMs). Idempotent.
  void stop();

  // Rounds of lcm_handle_timeout that failed (the bus's socket broke): counted, and the
  // thread backs off rather than spinning.
  std::uint64_t errors() const { return errors_.load(std::memory_order_relaxed); }

  static constexpr int kWaitMs = 100;

 private:
  void loop();

  lcm_t* lcm_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> errors_{0};
  std::thread thread_;
};

}  // namespace ccdlane
