// The vehicle's latest state from the bus (vehicle_state_t, as a CAN gateway publishes
// it): received on the LCM thread, read by the processing thread at each frame, through
// a seqlock (no lock, no allocation per message, never a torn value).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include <lcm/lcm.h>

#include "base/log.hpp"
#include "base/turn_indicator.hpp"
#include "bus/vehicle_state_check.hpp"
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
  // The first refusal of each cause is logged to `log` (the process log when empty).
  VehicleStateListener(lcm_t* lcm, const std::string& channel, LogSink log = {});
  ~VehicleStateListener();
  VehicleStateListener(const VehicleStateListener&) = delete;
  VehicleStateListener& operator=(const VehicleStateListener&) = delete;

  // The latest valid message, if any arrived. Any thread; lock-free, allocation-free.
  std::optional<VehicleState> latest() const;

  // Messages taken, and refused (vehicle_state_check.hpp: undecodable, or a field beyond
  // its physical bounds), in all and by cause.
  std::uint64_t received() const { return received_.load(std::memory_order_relaxed); }
  std::uint64_t rejected() const;
  std::uint64_t rejected(VehicleRefusal why) const {
    return refused_[static_cast<std::size_t>(why)].load(std::memory_order_relaxed);
  }
  // The gateway at now_ns: none heard, delivering, or at fault (only refused states, or
  // silent for longer than max_age_ns after it was heard). Any thread, allocation-free.
  GatewayState gateway(std::int64_t now_ns, std::int64_t max_age_ns) const;
  GatewayCounters counters(std::int64_t now_ns, std::int64_t max_age_ns) const;

  // For tests and other transports: what a message's handler does, at `received_ns`.
  // One writer at a time (the LCM thread).
  bool accept(const void* data, int size, std::int64_t received_ns);

 private:
  static void on_message(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  void store(const VehicleState& s);
  void refuse(VehicleRefusal why, const vehicle_state_t& m, int size);

  lcm_t* lcm_ = nullptr;
  std::string channel_;
  LogSink log_;
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
  std::atomic<std::uint64_t> received_{0};
  std::array<std::atomic<std::uint64_t>, kVehicleRefusalKinds> refused_{};
  std::array<std::atomic<bool>, kVehicleRefusalKinds> said_{};  // each cause is logged once
};

// How old a vehicle state may be and still count (gateways publish at 10 Hz or faster):
// older, the gateway has stopped, and its last indicator (or speed) must not hold.
inline constexpr std::int64_t kVehicleStateMaxAgeNs = 500'000'000;

// A frame's vehicle inputs from the latest state: empty (the estimator then uses
// [vehicle] speed_kmh, no yaw rate, no indicator) when there is none or it is older than
// max_age_ns at now_ns (the gateway stopped: its last indicator must not hold forever).
VehicleInputs vehicle_inputs(const std::optional<VehicleState>& state, std::int64_t now_ns, std::int64_t max_age_ns);

// The same from the listener, with vehicle_ok false while its gateway is at fault: the
// configured speed is for a vehicle without a gateway, not for a broken one.
VehicleInputs vehicle_inputs(const VehicleStateListener& listener, std::int64_t now_ns, std::int64_t max_age_ns);

}  // namespace ccdlane
