// A fixed-size history of gyro samples, written by the gyro thread and read by the
// processing thread: the sensor attitude at a frame's timestamp, interpolated, with
// "no data", "stale" and "out of range" said plainly.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "base/gx1_angles.hpp"

namespace ccdlane::gx1 {

// One sensor reading: angles as the sensor reports them (docs/gx1.md section 4, degrees),
// stamped with CLOCK_MONOTONIC when its last byte arrived.
struct Gx1Sample {
  std::int64_t t_ns = 0;
  std::uint16_t ticks = 0;
  Gx1Angles angles;
  // The angular rate about the sensor's x, y, z axes, rad/s (the 0x31 reply's
  // drift-compensated rate vector, scaled by the unit's gyro gain); a 0x0E stream has none.
  bool has_rate = false;
  std::array<double, 3> rate_radps{};
};

enum class AttitudeStatus : std::uint8_t {
  ok,
  no_data,       // nothing received yet
  stale,         // the samples around t (or the newest, for t after it) are too far from t
  out_of_range,  // t is before the oldest sample still kept
};
const char* to_string(AttitudeStatus status);

struct AttitudeQuery {
  AttitudeStatus status = AttitudeStatus::no_data;
  Gx1Angles angles;  // meaningful for ok and stale
  // How far the answer reaches from real samples: for t after the newest sample,
  // t - t_newest (the newest is held, never extrapolated); between two samples, the
  // time between them (0 on an exact hit). Stale when it exceeds the allowed age.
  std::int64_t gap_ns = 0;
  // The angular rate (sensor axes, rad/s) at t, interpolated like the angles, when the
  // samples around t (or the newest) carry one.
  bool has_rate = false;
  std::array<double, 3> rate_radps{};
};

// The rate of the sensor's yaw angle (about the Earth's down axis, rad/s, + clockwise seen
// from above) from its body rates and its roll and pitch: the 3-2-1 Euler kinematics,
// psi' = (q sin(roll) + r cos(roll)) / cos(pitch).
double yaw_angle_rate_radps(const Gx1Angles& angles, const std::array<double, 3>& body_rate_radps);

// Angles interpolated linearly along the shorter arc, so yaw going from +179 to -179
// degrees passes through 180, not 0 (roll too; pitch never wraps).
Gx1Angles interpolate_angles(const Gx1Angles& a, const Gx1Angles& b, double fraction);

// Single writer, any number of readers, no locks and no allocation: a sequence lock
// over the ring. The writer never waits for a reader (the gyro thread must keep
// reading the line); a reader that raced a write retries, which takes well under a
// microsecond against writes every few milliseconds.
class AttitudeHistory {
 public:
  static constexpr std::size_t kCapacity = 1024;  // 10 s at 100 Hz

  // Writer only. Timestamps are kept non-decreasing (a sample stamped earlier than its
  // predecessor is stamped with the predecessor's time).
  void push(const Gx1Sample& sample);

  AttitudeQuery attitude_at(std::int64_t t_ns, std::int64_t max_age_ns) const;

  // Samples pushed so far; sample(i) is the i-th of them while it is still kept.
  std::uint64_t count() const { return count_.load(std::memory_order_acquire); }
  bool sample(std::uint64_t index, Gx1Sample& out) const;

 private:
  struct Slot {
    std::atomic<std::int64_t> t_ns{0};
    std::atomic<std::uint32_t> ticks{0};
    std::atomic<double> roll{0.0}, pitch{0.0}, yaw{0.0};
    std::atomic<bool> has_rate{false};
    std::atomic<double> rate_x{0.0}, rate_y{0.0}, rate_z{0.0};
  };
  Gx1Sample load(std::uint64_t index) const;
  std::int64_t t_of(std::uint64_t index) const {
    return slots_[index % kCapacity].t_ns.load(std::memory_order_acquire);
  }
  template <typename Read>
  auto read_consistent(Read read) const;

  std::array<Slot, kCapacity> slots_;
  std::atomic<std::uint64_t> sequence_{0};  // odd while a write is in progress
  std::atomic<std::uint64_t> count_{0};
  std::int64_t last_t_ns_ = 0;  // writer only
};

}  // namespace ccdlane::gx1
