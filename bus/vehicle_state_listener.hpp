// The vehicle's latest state from the bus (vehicle_state_t, as a CAN gateway publishes
// it): received on the LCM thread, read by the processing thread at each frame, through
// a seqlock (no lock, no allocation per message, never a torn value).
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include <lcm/lcm.h>

#include "base/turn_indicator.hpp"
#include "core/lane/lane_estimator.hpp"

namespace ccdlane {

struct VehicleState {
  std::int64_t utime = 0;        // the gateway's, microseconds since the Unix epoch
  std::int64_t received_ns = 0;  // when it arrived here, CLOCK_MONOTONIC
  double speed_mps = 0.0;
  std::optional<double> yaw_rate_radps;  // + turning left
  TurnIndicator indicator = TurnIndicator::none;
};

class VehicleStateListener {
 public:
  // Subscribes to `channel` on `lcm` (not owned; it must outlive the listener). Messages
  // arrive while the owner of `lcm` handles it (lcm_handle / LCM::handle*), on that thread.
  VehicleStateListener(lcm_t* lcm, const std::string& channel);
  ~VehicleStateListener();
  VehicleStateListener(const VehicleStateListener&) = delete;
  VehicleStateListener& operator=(const VehicleStateListener&) = delete;

  // The latest valid message, if any arrived. Any thread; lock-free, allocation-free.
  std::optional<VehicleState> latest() const;

  // Messages taken, and refused (undecodable; a negative or non-finite speed; a
  // non-finite yaw rate; an unknown indicator code).
  std::uint64_t received() const { return received_.load(std::memory_order_relaxed); }
  std::uint64_t rejected() const { return rejected_.load(std::memory_order_relaxed); }

  // For tests and other transports: what a message's handler does, at `received_ns`.
  // One writer at a time (the LCM thread).
  bool accept(const void* data, int size, std::int64_t received_ns);

 private:
  static void on_message(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  void store(const VehicleState& s);

  lcm_t* lcm_ = nullptr;
  lcm_subscription_t* subscription_ = nullptr;
  // Seqlock (Boehm, "Can seqlocks get along with programming language memory models?"):
  // odd while the writer is between its two increments; every field is an atomic read
  // and written relaxed, so a reader racing the writer sees a changed sequence, never a
  // data race.
  std::atomic<std::uint64_t> sequence_{0};
  std::atomic<std::int64_t> utime_{0}, received_ns_{0};
  std::atomic<double> speed_mps_{0.0}, yaw_rate_radps_{0.0};
  std::atomic<bool> has_yaw_rate_{false};
  std::atomic<std::uint8_t> indicator_{0};
  std::atomic<std::uint64_t> received_{0}, rejected_{0};
};

// How old a vehicle state may be and still count (gateways publish at 10 Hz or faster):
// older, the gateway has stopped, and its last indicator (or speed) must not hold.
inline constexpr std::int64_t kVehicleStateMaxAgeNs = 500'000'000;

// A frame's vehicle inputs from the latest state: empty (the estimator then uses
// [vehicle] speed_kmh, no yaw rate, no indicator) when there is none or it is older than
// max_age_ns at now_ns (the gateway stopped: its last indicator must not hold forever).
VehicleInputs vehicle_inputs(const std::optional<VehicleState>& state, std::int64_t now_ns, std::int64_t max_age_ns);

}  // namespace ccdlane
