// The gyro history: interpolation (across the +-180 degree wrap), "no data", "stale" and
// "out of range", and a writer and readers racing (run under ThreadSanitizer too).
#include "drivers/gx1/attitude_history.hpp"

#include <atomic>
#include <cmath>
#include <memory>
#include <numbers>
#include <thread>

#include <gtest/gtest.h>

namespace ccdlane::gx1 {
namespace {

constexpr std::int64_t kMs = 1'000'000;

Gx1Sample at(std::int64_t t_ns, double roll, double pitch, double yaw) {
  return {t_ns, static_cast<std::uint16_t>(t_ns / kMs), {roll, pitch, yaw}};
}

TEST(AttitudeHistory, EmptyHasNoData) {
  AttitudeHistory h;
  EXPECT_EQ(h.attitude_at(0, 100 * kMs).status, AttitudeStatus::no_data);
  EXPECT_EQ(h.count(), 0u);
  Gx1Sample s;
  EXPECT_FALSE(h.sample(0, s));
}

TEST(AttitudeHistory, ExactHitAndLinearInterpolation) {
  AttitudeHistory h;
  h.push(at(1000 * kMs, 10.0, -4.0, 30.0));
  h.push(at(1010 * kMs, 12.0, -5.0, 40.0));
  const AttitudeQuery hit = h.attitude_at(1000 * kMs, 100 * kMs);
  EXPECT_EQ(hit.status, AttitudeStatus::ok);
  EXPECT_EQ(hit.gap_ns, 0);
  EXPECT_DOUBLE_EQ(hit.angles.roll_deg, 10.0);
  const AttitudeQuery q = h.attitude_at(1002500000, 100 * kMs);  // a quarter of the way
  EXPECT_EQ(q.status, AttitudeStatus::ok);
  EXPECT_EQ(q.gap_ns, 10 * kMs);
  EXPECT_DOUBLE_EQ(q.angles.roll_deg, 10.5);
  EXPECT_DOUBLE_EQ(q.angles.pitch_deg, -4.25);
  EXPECT_DOUBLE_EQ(q.angles.yaw_deg, 32.5);
}

Gx1Sample with_rate(Gx1Sample s, double x, double y, double z) {
  s.has_rate = true;
  s.rate_radps = {x, y, z};
  return s;
}

TEST(AttitudeHistory, RatesAreKeptAndInterpolatedLikeTheAngles) {
  AttitudeHistory h;
  h.push(with_rate(at(1000 * kMs, 0.0, 0.0, 0.0), 0.1, -0.2, 0.3));
  h.push(with_rate(at(1010 * kMs, 0.0, 0.0, 0.0), 0.3, -0.2, 0.5));
  const AttitudeQuery q = h.attitude_at(1002500000, 100 * kMs);  // a quarter of the way
  ASSERT_TRUE(q.has_rate);
  EXPECT_DOUBLE_EQ(q.rate_radps[0], 0.15);
  EXPECT_DOUBLE_EQ(q.rate_radps[1], -0.2);
  EXPECT_DOUBLE_EQ(q.rate_radps[2], 0.35);
  const AttitudeQuery after = h.attitude_at(1020 * kMs, 100 * kMs);  // the newest, held
  ASSERT_TRUE(after.has_rate);
  EXPECT_DOUBLE_EQ(after.rate_radps[2], 0.5);
  h.push(at(1020 * kMs, 0.0, 0.0, 0.0));  // a sample without a rate (a 0x0E reply)
  EXPECT_FALSE(h.attitude_at(1015 * kMs, 100 * kMs).has_rate) << "no rate made up from one side";
  Gx1Sample s;
  ASSERT_TRUE(h.sample(0, s));
  EXPECT_TRUE(s.has_rate);
  EXPECT_DOUBLE_EQ(s.rate_radps[0], 0.1);
}

TEST(AttitudeHistory, TheYawAngleRateFollowsTheEulerKinematics) {
  // Level, the yaw angle turns at the z rate; rolled 90 degrees, at the y rate.
  EXPECT_DOUBLE_EQ(yaw_angle_rate_radps({0.0, 0.0, 50.0}, {0.7, 0.0, 0.25}), 0.25);
  EXPECT_NEAR(yaw_angle_rate_radps({90.0, 0.0, 50.0}, {0.0, 0.25, 0.9}), 0.25, 1e-12);
  // Any attitude: body rates made from Euler angle rates by the 3-2-1 relations
  // (p = roll' - yaw' sin(pitch), q = pitch' cos(roll) + yaw' cos(pitch) sin(roll),
  // r = -pitch' sin(roll) + yaw' cos(pitch) cos(roll)) give back yaw'.
  const double roll = 0.3, pitch = -0.5, roll_rate = 0.1, pitch_rate = -0.2, yaw_rate = 0.35;
  const std::array<double, 3> body = {roll_rate - yaw_rate * std::sin(pitch),
                                      pitch_rate * std::cos(roll) + yaw_rate * std::cos(pitch) * std::sin(roll),
                                      -pitch_rate * std::sin(roll) + yaw_rate * std::cos(pitch) * std::cos(roll)};
  const double deg = 180.0 / std::numbers::pi;
  EXPECT_NEAR(yaw_angle_rate_radps({roll * deg, pitch * deg, 10.0}, body), yaw_rate, 1e-12);
}

TEST(AttitudeHistory, YawAndRollInterpolateAcrossTheWrap) {
  AttitudeHistory h;
  h.push(at(0, 178.0, 0.0, 179.0));
  h.push(at(10 * kMs, -178.0, 0.0, -179.0));
  const AttitudeQuery quarter = h.attitude_at(2500000, 100 * kMs);
  EXPECT_NEAR(quarter.angles.yaw_deg, 179.5, 1e-12);
  EXPECT_NEAR(quarter.angles.roll_deg, 179.0, 1e-12);
  const AttitudeQuery three_quarters = h.attitude_at(7500000, 100 * kMs);
  EXPECT_NEAR(three_quarters.angles.yaw_deg, -179.5, 1e-12);
  EXPECT_NEAR(three_quarters.angles.roll_deg, -179.0, 1e-12);
  const AttitudeQuery half = h.attitude_at(5 * kMs, 100 * kMs);
  EXPECT_NEAR(std::abs(half.angles.yaw_deg), 180.0, 1e-12);  // not 0, as a naive average would say
}

TEST(AttitudeHistory, InterpolateAnglesTakesTheShorterArc) {
  const Gx1Angles a{-170.0, 10.0, 170.0}, b{170.0, 20.0, -170.0};
  const Gx1Angles m = interpolate_angles(a, b, 0.5);
  EXPECT_NEAR(std::abs(m.roll_deg), 180.0, 1e-12);
  EXPECT_NEAR(m.pitch_deg, 15.0, 1e-12);
  EXPECT_NEAR(std::abs(m.yaw_deg), 180.0, 1e-12);
  EXPECT_NEAR(interpolate_angles(a, b, 0.25).yaw_deg, 175.0, 1e-12);
}

TEST(AttitudeHistory, AfterTheNewestHoldsItThenGoesStale) {
  AttitudeHistory h;
  h.push(at(0, 1.0, 2.0, 3.0));
  h.push(at(10 * kMs, 4.0, 5.0, 6.0));
  const AttitudeQuery fresh = h.attitude_at(60 * kMs, 100 * kMs);
  EXPECT_EQ(fresh.status, AttitudeStatus::ok);
  EXPECT_EQ(fresh.gap_ns, 50 * kMs);
  EXPECT_DOUBLE_EQ(fresh.angles.yaw_deg, 6.0);  // held, not extrapolated
  const AttitudeQuery old = h.attitude_at(111 * kMs, 100 * kMs);
  EXPECT_EQ(old.status, AttitudeStatus::stale);
  EXPECT_DOUBLE_EQ(old.angles.yaw_deg, 6.0);
}

TEST(AttitudeHistory, AGapWiderThanTheMaxAgeIsStale) {
  AttitudeHistory h;  // the sensor was unplugged for 2 s between the two samples
  h.push(at(0, 0.0, 0.0, 0.0));
  h.push(at(2000 * kMs, 20.0, 0.0, 0.0));
  const AttitudeQuery q = h.attitude_at(1000 * kMs, 100 * kMs);
  EXPECT_EQ(q.status, AttitudeStatus::stale);
  EXPECT_EQ(q.gap_ns, 2000 * kMs);
  EXPECT_EQ(h.attitude_at(2000 * kMs, 100 * kMs).status, AttitudeStatus::ok);  // exact hit
}

TEST(AttitudeHistory, BeforeTheOldestKeptIsOutOfRange) {
  AttitudeHistory h;
  h.push(at(100 * kMs, 0.0, 0.0, 0.0));
  EXPECT_EQ(h.attitude_at(99 * kMs, 100 * kMs).status, AttitudeStatus::out_of_range);
  for (std::size_t i = 1; i < AttitudeHistory::kCapacity + 10; ++i)
    h.push(at(100 * kMs + static_cast<std::int64_t>(i) * kMs, 0.0, 0.0, 0.0));
  // The first 10 samples have been overwritten.
  EXPECT_EQ(h.attitude_at(109 * kMs, 100 * kMs).status, AttitudeStatus::out_of_range);
  EXPECT_EQ(h.attitude_at(110 * kMs, 100 * kMs).status, AttitudeStatus::ok);
  Gx1Sample s;
  EXPECT_FALSE(h.sample(9, s));
  ASSERT_TRUE(h.sample(10, s));
  EXPECT_EQ(s.t_ns, 110 * kMs);
  EXPECT_FALSE(h.sample(h.count(), s));
}

TEST(AttitudeHistory, KeepsTimestampsNonDecreasing) {
  AttitudeHistory h;
  h.push(at(50 * kMs, 1.0, 0.0, 0.0));
  h.push(at(40 * kMs, 2.0, 0.0, 0.0));  // stamped earlier than its predecessor
  Gx1Sample s;
  ASSERT_TRUE(h.sample(1, s));
  EXPECT_EQ(s.t_ns, 50 * kMs);
  EXPECT_DOUBLE_EQ(s.angles.roll_deg, 2.0);
}

// A writer pushes samples of a known line (roll = 0.01 degree per ms, wrapping at
// +-180; pitch = -roll; yaw = roll + 90) as fast as it can, overwriting the ring many
// times; readers query near the newest samples and near the oldest, which the writer
// is about to overwrite. A read that mixed two samples, or a slot from another lap,
// would be off the line.
TEST(AttitudeHistory, ReadersNeverSeeATornSample) {
  auto h = std::make_unique<AttitudeHistory>();
  constexpr int kSamples = 500000;
  const auto line = [](double t_ms) { return std::remainder(t_ms * 0.01, 360.0); };
  const auto off_line = [](double a, double b) { return std::abs(std::remainder(a - b, 360.0)) > 1e-6; };
  for (int i = 0; i < 2; ++i) h->push(at(std::int64_t{i} * kMs, line(i), -line(i), line(i + 9000)));
  std::atomic<bool> done{false};
  std::atomic<long> checked{0};
  std::thread writer([&] {
    for (int i = 2; i < kSamples; ++i) {
      h->push(at(std::int64_t{i} * kMs, line(i), -line(i), line(i + 9000)));
    }
    done = true;
  });
  auto read = [&] {
    long n = 0;
    while (!done || n < 1000) {
      const std::uint64_t count = h->count();
      const std::uint64_t base =
          n % 2 ? count - 2 : (count > AttitudeHistory::kCapacity ? count - AttitudeHistory::kCapacity : 0);
      const std::int64_t t = static_cast<std::int64_t>(base) * kMs + kMs / 2;
      const AttitudeQuery q = h->attitude_at(t, 10 * kMs);
      ++n;
      if (q.status == AttitudeStatus::out_of_range) continue;  // overwritten meanwhile: fine
      const double expected = line(static_cast<double>(t) / kMs);
      if (q.status == AttitudeStatus::no_data || off_line(q.angles.roll_deg, expected) ||
          off_line(q.angles.pitch_deg, -q.angles.roll_deg) || off_line(q.angles.yaw_deg, q.angles.roll_deg + 90.0)) {
        ADD_FAILURE() << "inconsistent read at t " << t << ": roll " << q.angles.roll_deg << " expected " << expected;
        return;
      }
    }
    checked += n;
  };
  std::thread r1(read), r2(read);
  writer.join();
  r1.join();
  r2.join();
  EXPECT_GE(checked.load(), 2000);
}

}  // namespace
}  // namespace ccdlane::gx1
