// The gyro sample history: a seqlock-protected ring (writes: gyro thread; reads: anyone).
#include "drivers/gx1/attitude_history.hpp"

#include <cmath>
#include <numbers>

namespace ccdlane::gx1 {
namespace {

// Into [-180, 180).
double wrap_degrees(double d) {
  const double w = std::fmod(d + 180.0, 360.0);
  return (w < 0.0 ? w + 360.0 : w) - 180.0;
}

double interpolate_angle(double a, double b, double fraction) {
  return wrap_degrees(a + fraction * wrap_degrees(b - a));
}

}  // namespace

const char* to_string(AttitudeStatus status) {
  switch (status) {
    case AttitudeStatus::ok: return "ok";
    case AttitudeStatus::no_data: return "no data";
    case AttitudeStatus::stale: return "stale";
    case AttitudeStatus::out_of_range: return "out of range";
  }
  return "?";
}

Gx1Angles interpolate_angles(const Gx1Angles& a, const Gx1Angles& b, double fraction) {
  return {interpolate_angle(a.roll_deg, b.roll_deg, fraction), interpolate_angle(a.pitch_deg, b.pitch_deg, fraction),
          interpolate_angle(a.yaw_deg, b.yaw_deg, fraction)};
}

// The sequence lock without standalone fences (which ThreadSanitizer cannot model):
// every slot store is a release and every slot load an acquire, so a reader that sees
// any value of a write also sees the odd sequence number stored before it (Boehm,
// "Can seqlocks get along with programming language memory models?", 2012). On x86
// these are plain moves.
void AttitudeHistory::push(const Gx1Sample& sample) {
  constexpr auto release = std::memory_order_release;
  const std::uint64_t n = count_.load(std::memory_order_relaxed);
  const std::int64_t t = n > 0 && sample.t_ns < last_t_ns_ ? last_t_ns_ : sample.t_ns;
  last_t_ns_ = t;
  const std::uint64_t seq = sequence_.load(std::memory_order_relaxed);
  sequence_.store(seq + 1, std::memory_order_relaxed);
  Slot& s = slots_[n % kCapacity];
  s.t_ns.store(t, release);
  s.ticks.store(sample.ticks, release);
  s.roll.store(sample.angles.roll_deg, release);
  s.pitch.store(sample.angles.pitch_deg, release);
  s.yaw.store(sample.angles.yaw_deg, release);
  s.has_rate.store(sample.has_rate, release);
  s.rate_x.store(sample.rate_radps[0], release);
  s.rate_y.store(sample.rate_radps[1], release);
  s.rate_z.store(sample.rate_radps[2], release);
  count_.store(n + 1, release);
  sequence_.store(seq + 2, release);
}

Gx1Sample AttitudeHistory::load(std::uint64_t index) const {
  constexpr auto acquire = std::memory_order_acquire;
  const Slot& s = slots_[index % kCapacity];
  return {s.t_ns.load(acquire),
          static_cast<std::uint16_t>(s.ticks.load(acquire)),
          {s.roll.load(acquire), s.pitch.load(acquire), s.yaw.load(acquire)},
          s.has_rate.load(acquire),
          {s.rate_x.load(acquire), s.rate_y.load(acquire), s.rate_z.load(acquire)}};
}

// Runs `read` until it ran while no write was in progress and none started meanwhile.
template <typename Read>
auto AttitudeHistory::read_consistent(Read read) const {
  for (;;) {
    const std::uint64_t before = sequence_.load(std::memory_order_acquire);
    if (before & 1) continue;
    auto result = read();
    if (sequence_.load(std::memory_order_relaxed) == before) return result;
  }
}

bool AttitudeHistory::sample(std::uint64_t index, Gx1Sample& out) const {
  struct Result {
    bool kept;
    Gx1Sample sample;
  };
  const Result r = read_consistent([&] {
    const std::uint64_t n = count_.load(std::memory_order_acquire);
    if (index >= n || n - index > kCapacity) return Result{false, {}};
    return Result{true, load(index)};
  });
  if (r.kept) out = r.sample;
  return r.kept;
}

AttitudeQuery AttitudeHistory::attitude_at(std::int64_t t_ns, std::int64_t max_age_ns) const {
  return read_consistent([&] {
    AttitudeQuery q;
    const std::uint64_t n = count_.load(std::memory_order_acquire);
    if (n == 0) return q;  // no_data
    const std::uint64_t first = n > kCapacity ? n - kCapacity : 0;
    if (t_ns < t_of(first)) {
      q.status = AttitudeStatus::out_of_range;
      return q;
    }
    if (t_ns >= t_of(n - 1)) {
      const Gx1Sample newest = load(n - 1);
      q.angles = newest.angles;
      q.has_rate = newest.has_rate;
      q.rate_radps = newest.rate_radps;
      q.gap_ns = t_ns - t_of(n - 1);
    } else {
      // First sample after t: t_of(hi - 1) <= t < t_of(hi).
      std::uint64_t lo = first, hi = n - 1;
      while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (t_of(mid) > t_ns)
          hi = mid;
        else
          lo = mid + 1;
      }
      const Gx1Sample a = load(hi - 1), b = load(hi);
      const std::int64_t span = b.t_ns - a.t_ns;
      const double fraction = span > 0 ? static_cast<double>(t_ns - a.t_ns) / static_cast<double>(span) : 0.0;
      q.angles = interpolate_angles(a.angles, b.angles, fraction);
      q.has_rate = a.has_rate && b.has_rate;
      for (std::size_t i = 0; i < 3; ++i)
        q.rate_radps[i] = a.rate_radps[i] + fraction * (b.rate_radps[i] - a.rate_radps[i]);
      q.gap_ns = t_ns == a.t_ns ? 0 : span;
    }
    q.status = q.gap_ns > max_age_ns ? AttitudeStatus::stale : AttitudeStatus::ok;
    return q;
  });
}

double yaw_angle_rate_radps(const Gx1Angles& angles, const std::array<double, 3>& body_rate_radps) {
  constexpr double kRadPerDeg = std::numbers::pi / 180.0;
  const double roll = angles.roll_deg * kRadPerDeg, pitch = angles.pitch_deg * kRadPerDeg;
  return (body_rate_radps[1] * std::sin(roll) + body_rate_radps[2] * std::cos(roll)) / std::cos(pitch);
}

}  // namespace ccdlane::gx1
