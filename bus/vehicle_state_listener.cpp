// vehicle_state_t off the bus into a seqlock. The C API is used for the subscription:
// its handler gets the channel as a char pointer, where the C++ wrapper builds a
// std::string per message.
#include "bus/vehicle_state_listener.hpp"

#include <utility>

#include <ccdlane/vehicle_state_t.hpp>

#include "base/clock.hpp"

namespace ccdlane {

static_assert(vehicle_state_t::TURN_INDICATOR_NONE == static_cast<int>(TurnIndicator::none));
static_assert(vehicle_state_t::TURN_INDICATOR_LEFT == static_cast<int>(TurnIndicator::left));
static_assert(vehicle_state_t::TURN_INDICATOR_RIGHT == static_cast<int>(TurnIndicator::right));
static_assert(vehicle_state_t::TURN_INDICATOR_BOTH == static_cast<int>(TurnIndicator::both));

VehicleStateListener::VehicleStateListener(lcm_t* lcm, const std::string& channel, LogSink log)
    : lcm_(lcm), channel_(channel), log_(std::move(log)) {
  if (lcm_) subscription_ = lcm_subscribe(lcm_, channel.c_str(), &VehicleStateListener::on_message, this);
}

VehicleStateListener::~VehicleStateListener() {
  if (lcm_ && subscription_) lcm_unsubscribe(lcm_, subscription_);
}

void VehicleStateListener::on_message(const lcm_recv_buf_t* rbuf, const char*, void* self) {
  static_cast<VehicleStateListener*>(self)->accept(rbuf->data, static_cast<int>(rbuf->data_size), monotonic_ns());
}

bool VehicleStateListener::accept(const void* data, int size, std::int64_t received_ns) {
  vehicle_state_t m{};
  const std::optional<VehicleRefusal> why =
      m.decode(data, 0, size) == size ? vehicle_state_refusal(m) : VehicleRefusal::undecodable;
  if (why) {
    refuse(*why, m, size);
    return false;
  }
  VehicleState s;
  s.utime = m.utime;
  s.received_ns = received_ns;
  s.speed_mps = m.speed_mps;
  if (m.has_yaw_rate) s.yaw_rate_radps = m.yaw_rate_radps;
  s.indicator = static_cast<TurnIndicator>(m.turn_indicator);
  store(s);
  received_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

void VehicleStateListener::refuse(VehicleRefusal why, const vehicle_state_t& m, int size) {
  const auto i = static_cast<std::size_t>(why);
  refused_[i].fetch_add(1, std::memory_order_relaxed);
  if (!first_time(said_[i])) return;  // counted in status_t.vehicle_refused_by_cause
  if (why == VehicleRefusal::undecodable) {
    log_to(log_, LogLevel::warning, "vehicle",
           "%s: refused a message of %d bytes that is no vehicle_state_t (another type, truncated or damaged); "
           "LDW is unavailable (vehicle_fault) until good states come (said once per cause)",
           channel_.c_str(), size);
    return;
  }
  log_to(log_, LogLevel::warning, "vehicle",
         "%s: refused a vehicle_state_t for its %s (speed %g m/s, yaw rate %g rad/s%s, indicator %d; bounds: speed "
         "0..%g m/s, |yaw rate| <= %g rad/s, indicator 0..3); LDW is unavailable (vehicle_fault) until good states "
         "come (said once per cause)",
         channel_.c_str(), to_string(why), m.speed_mps, m.yaw_rate_radps, m.has_yaw_rate ? "" : " (not reported)",
         int{m.turn_indicator}, kMaxVehicleSpeedMps, kMaxVehicleYawRateRadps);
}

std::uint64_t VehicleStateListener::rejected() const {
  std::uint64_t n = 0;
  for (const auto& c : refused_) n += c.load(std::memory_order_relaxed);
  return n;
}

GatewayState VehicleStateListener::gateway(std::int64_t now_ns, std::int64_t max_age_ns) const {
  const bool heard = received() + rejected() > 0;
  const std::optional<VehicleState> s = latest();
  return gateway_state(heard, s ? std::optional<std::int64_t>(s->received_ns) : std::nullopt, now_ns, max_age_ns);
}

GatewayCounters VehicleStateListener::counters(std::int64_t now_ns, std::int64_t max_age_ns) const {
  GatewayCounters c;
  c.state = gateway(now_ns, max_age_ns);
  c.taken = received();
  for (std::size_t i = 0; i < c.refused.size(); ++i) c.refused[i] = refused_[i].load(std::memory_order_relaxed);
  return c;
}

void VehicleStateListener::store(const VehicleState& s) {
  // Without fences (which ThreadSanitizer cannot follow): the odd count is published by
  // an acq_rel increment, and every field is a release store, so a reader whose acquire
  // load sees any new field also sees the odd count on its second look and retries.
  const std::uint64_t seq = sequence_.fetch_add(1, std::memory_order_acq_rel);
  utime_.store(s.utime, std::memory_order_release);
  received_ns_.store(s.received_ns, std::memory_order_release);
  speed_mps_.store(s.speed_mps, std::memory_order_release);
  has_yaw_rate_.store(s.yaw_rate_radps.has_value(), std::memory_order_release);
  yaw_rate_radps_.store(s.yaw_rate_radps.value_or(0.0), std::memory_order_release);
  indicator_.store(static_cast<std::uint8_t>(s.indicator), std::memory_order_release);
  sequence_.store(seq + 2, std::memory_order_release);
}

std::optional<VehicleState> VehicleStateListener::latest() const {
  for (;;) {
    const std::uint64_t before = sequence_.load(std::memory_order_acquire);
    if (before == 0) return std::nullopt;  // nothing yet
    if (before & 1U) continue;             // the writer is between its stores
    VehicleState s;
    s.utime = utime_.load(std::memory_order_acquire);
    s.received_ns = received_ns_.load(std::memory_order_acquire);
    s.speed_mps = speed_mps_.load(std::memory_order_acquire);
    const bool has_yaw_rate = has_yaw_rate_.load(std::memory_order_acquire);
    const double yaw_rate = yaw_rate_radps_.load(std::memory_order_acquire);
    s.indicator = static_cast<TurnIndicator>(indicator_.load(std::memory_order_acquire));
    if (sequence_.load(std::memory_order_acquire) != before) continue;
    if (has_yaw_rate) s.yaw_rate_radps = yaw_rate;
    return s;
  }
}

VehicleInputs vehicle_inputs(const std::optional<VehicleState>& state, std::int64_t now_ns, std::int64_t max_age_ns) {
  VehicleInputs in;
  if (!state || now_ns - state->received_ns > max_age_ns) return in;
  in.speed_mps = state->speed_mps;
  in.yaw_rate_radps = state->yaw_rate_radps;
  in.indicator = state->indicator;
  return in;
}

VehicleInputs vehicle_inputs(const VehicleStateListener& listener, std::int64_t now_ns, std::int64_t max_age_ns) {
  VehicleInputs in = vehicle_inputs(listener.latest(), now_ns, max_age_ns);
  in.vehicle_ok = listener.gateway(now_ns, max_age_ns) != GatewayState::fault;
  return in;
}

}  // namespace ccdlane
