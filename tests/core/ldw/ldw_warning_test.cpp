// The warning decision on hand-made inputs: where the threshold lies, one warning per
// departure, re-arming, the indicator (and its hold time), the speed gate with its
// hysteresis, the availability reasons and their precedence, and the names.
#include "core/ldw/ldw_warning.hpp"

#include <gtest/gtest.h>

namespace ccdlane::ldw {
namespace {

constexpr double kDt = 1.0 / 30;
constexpr double kHighway = 72.0 / 3.6;

// A vehicle moving laterally at `v` (+ left) with the left wheel's DLC `left` (the right
// one at 2 m minus it, as in a lane with 1.8 m of room).
LdwInput input(double t, double left_dlc, double v, TurnIndicator indicator = TurnIndicator::none) {
  LdwInput in;
  in.t_s = t;
  in.speed_mps = kHighway;
  in.indicator = indicator;
  in.lane_tracked = true;
  in.left = {left_dlc, v, {}};
  in.right = {1.83 - left_dlc, -v, {}};
  return in;
}

// Ten frames standing at `dlc`.
void hold(LdwWarning& w, double& t, double dlc, TurnIndicator indicator = TurnIndicator::none) {
  for (int i = 0; i < 10; ++i, t += kDt) EXPECT_EQ(w.update(input(t, dlc, 0.0, indicator)).fired, Side::none);
}

// Drifts left at v from DLC `from` to `to`; returns the warnings fired and the DLC at the first.
struct Drift {
  int warnings = 0;
  double first_dlc = 0.0;
  double t = 0.0;
};
Drift drift(LdwWarning& w, double& t, double from, double to, double v, TurnIndicator indicator = TurnIndicator::none) {
  Drift d;
  const double step = (to < from ? -1 : 1) * std::abs(v) * kDt;
  for (double dlc = from; (step < 0 ? dlc >= to : dlc <= to); dlc += step, t += kDt) {
    const LdwOutput& o = w.update(input(t, dlc, v, indicator));
    if (o.fired != Side::none) {
      EXPECT_EQ(o.fired, v > 0 ? Side::left : Side::right);
      if (d.warnings++ == 0) d.first_dlc = dlc, d.t = t;
    }
  }
  return d;
}

TEST(LdwWarning, ThresholdGrowsWithTheApproachBetweenItsLimits) {
  const LdwWarning w;
  EXPECT_DOUBLE_EQ(w.threshold_mm(0.1), 100.0);  // slow: near the line
  EXPECT_DOUBLE_EQ(w.threshold_mm(0.5), 250.0);  // TLC 0.5 s
  EXPECT_DOUBLE_EQ(w.threshold_mm(1.0), 500.0);
  EXPECT_DOUBLE_EQ(w.threshold_mm(3.0), 600.0);  // never beyond 0.75 - 0.15 m
}

TEST(LdwWarning, WarnsOncePerDepartureAtTheThresholdForEveryStandardLateralVelocity) {
  for (const double v : {0.1, 0.3, 0.5, 0.8, 1.0}) {
    LdwWarning w;
    double t = 0.0;
    hold(w, t, 0.9);  // seen well inside: armed
    const Drift d = drift(w, t, 0.9, -0.6, v);
    EXPECT_EQ(d.warnings, 1) << v;
    EXPECT_LE(d.first_dlc * 1000.0, w.threshold_mm(v) + 1e-9) << v;
    EXPECT_GT(d.first_dlc * 1000.0, w.threshold_mm(v) - v * kDt * 1000.0 - 1e-9) << v;
    EXPECT_EQ(w.output().warnings, 1u);
  }
}

TEST(LdwWarning, WarningStaysSetForItsDurationThenClears) {
  LdwWarning w;
  double t = 0.0;
  hold(w, t, 0.9);
  const Drift d = drift(w, t, 0.9, 0.2, 0.5);
  ASSERT_EQ(d.warnings, 1);
  EXPECT_EQ(w.update(input(d.t + 0.9, 0.1, 0.5)).warning, Side::left);
  EXPECT_EQ(w.update(input(d.t + 1.01, 0.05, 0.5)).warning, Side::none);
}

TEST(LdwWarning, RearmsOnlyOnceTheWheelIsBackInsideByTheMargin) {
  LdwWarning w;
  double t = 0.0;
  hold(w, t, 0.9);
  ASSERT_EQ(drift(w, t, 0.9, 0.2, 0.5).warnings, 1);  // warned at 0.25 m
  drift(w, t, 0.2, 0.35, -0.2);                       // back to 0.35 m: not yet re-armed
  EXPECT_EQ(drift(w, t, 0.35, 0.0, 0.5).warnings, 0);
  drift(w, t, 0.0, 0.5, -0.2);  // back to 0.5 m (>= 0.45): re-armed
  EXPECT_EQ(drift(w, t, 0.5, 0.0, 0.5).warnings, 1);
  EXPECT_EQ(w.output().warnings, 2u);
}

TEST(LdwWarning, ABriefLossOfTheLaneAfterAWarningDoesNotWarnTheSameDepartureAgain) {
  LdwWarning w;
  double t = 0.0;
  hold(w, t, 0.9);
  const Drift first = drift(w, t, 0.9, 0.44, 1.0);  // warned at 0.5 m
  ASSERT_EQ(first.warnings, 1);
  LdwInput lost = input(t, 0.43, 1.0);
  lost.lane_tracked = false;
  w.update(lost);
  t += kDt;
  EXPECT_EQ(drift(w, t, 0.42, -0.3, 1.0).warnings, 0);  // 0.42 m is past the plain re-arm level
}

TEST(LdwWarning, DoesNotWarnAWheelThatIsNotApproaching) {
  LdwWarning w;
  double t = 0.0;
  hold(w, t, 0.9);
  for (int i = 0; i < 30; ++i, t += kDt) EXPECT_EQ(w.update(input(t, 0.05, 0.0)).fired, Side::none);
  for (int i = 0; i < 30; ++i, t += kDt) EXPECT_EQ(w.update(input(t, -0.1, -0.2)).fired, Side::none);
}

TEST(LdwWarning, RightSideMirrorsTheLeft) {
  LdwWarning w;
  double t = 0.0;
  hold(w, t, 0.9);
  // The left DLC growing means the right wheel (1.83 - left) approaches its line.
  const Drift d = drift(w, t, 0.9, 2.3, -0.5);
  EXPECT_EQ(d.warnings, 1);
  EXPECT_NEAR(1.83 - d.first_dlc, 0.25, 0.5 * kDt + 1e-9);
}

TEST(LdwWarning, IndicatorTowardTheSideSuppressesItAndHoldsAfterwards) {
  {  // On while crossing: no warning.
    LdwWarning w;
    double t = 0.0;
    hold(w, t, 0.9);
    EXPECT_EQ(drift(w, t, 0.9, -0.5, 0.8, TurnIndicator::left).warnings, 0);
    EXPECT_TRUE(w.output().suppressed_left);
    EXPECT_FALSE(w.output().suppressed_right);
  }
  {  // Toward the other side: warned.
    LdwWarning w;
    double t = 0.0;
    hold(w, t, 0.9);
    EXPECT_EQ(drift(w, t, 0.9, -0.5, 0.8, TurnIndicator::right).warnings, 1);
  }
  for (const auto& [gap_s, warned] : {std::pair{1.0, 0}, std::pair{2.5, 1}}) {
    // Off `gap_s` before the threshold is reached; held for 2 s.
    LdwWarning w;
    double t = 0.0;
    hold(w, t, 0.9, TurnIndicator::left);
    const double t_off = t;  // the next update sees it off
    hold(w, t, 0.9);
    const double start = 0.25 + 0.5 * (gap_s - (t - t_off));  // reaches 0.25 m at t_off + gap
    EXPECT_EQ(drift(w, t, start, -0.3, 0.5).warnings, warned) << gap_s;
  }
  {  // Hazard lights: both sides.
    LdwWarning w;
    double t = 0.0;
    hold(w, t, 0.9);
    EXPECT_EQ(drift(w, t, 0.9, -0.5, 0.8, TurnIndicator::both).warnings, 0);
    EXPECT_EQ(drift(w, t, 0.9, 2.3, -0.8, TurnIndicator::both).warnings, 0);
  }
}

TEST(LdwWarning, SignalledDepartureIsUsedUpNotWarnedWhenTheIndicatorGoesOffLate) {
  LdwWarning w;
  double t = 0.0;
  hold(w, t, 0.9);
  EXPECT_EQ(drift(w, t, 0.9, 0.0, 0.5, TurnIndicator::left).warnings, 0);
  w.update(input(t, 0.0, 0.0));  // the indicator goes off
  t += 3.0;                      // long after its hold time, the wheel still near the line and drifting
  EXPECT_EQ(drift(w, t, 0.0, -0.3, 0.5).warnings, 0);
}

TEST(LdwWarning, BelowTheMinimumSpeedItIsUnavailableWithHysteresis) {
  LdwWarning w;
  LdwInput in = input(0.0, 0.9, 0.0);
  in.speed_mps = 59.0 / 3.6;
  EXPECT_FALSE(w.update(in).available);
  EXPECT_EQ(w.output().reason, Availability::too_slow);
  in.speed_mps = 61.0 / 3.6;  // within the hysteresis: still too slow
  EXPECT_FALSE(w.update(in).available);
  in.speed_mps = 62.5 / 3.6;
  EXPECT_TRUE(w.update(in).available);
  in.speed_mps = 61.0 / 3.6;  // coming down through the band: still available
  EXPECT_TRUE(w.update(in).available);
  in.speed_mps = 59.9 / 3.6;
  EXPECT_FALSE(w.update(in).available);
  // A drift below the speed: no warning.
  double t = 1.0;
  for (double dlc = 0.9; dlc > -0.5; dlc -= 0.5 * kDt, t += kDt) {
    LdwInput slow = input(t, dlc, 0.5);
    slow.speed_mps = 50.0 / 3.6;
    EXPECT_EQ(w.update(slow).fired, Side::none);
  }
}

TEST(LdwWarning, ReportsTheFirstApplicableReason) {
  LdwWarning w;
  LdwInput in = input(0.0, 0.9, 0.0);
  in.speed_mps = 10.0;
  in.lane_tracked = false;
  in.calibrated = false;
  in.vehicle_ok = false;
  in.gyro_ok = false;
  in.camera_ok = false;
  EXPECT_EQ(w.update(in).reason, Availability::camera_fault);
  in.camera_ok = true;
  EXPECT_EQ(w.update(in).reason, Availability::gyro_fault);
  in.gyro_ok = true;
  EXPECT_EQ(w.update(in).reason, Availability::vehicle_fault);
  in.vehicle_ok = true;
  EXPECT_EQ(w.update(in).reason, Availability::not_calibrated);
  in.calibrated = true;
  EXPECT_EQ(w.update(in).reason, Availability::no_lane);
  in.lane_tracked = true;
  EXPECT_EQ(w.update(in).reason, Availability::too_slow);
  in.speed_mps = kHighway;
  EXPECT_EQ(w.update(in).reason, Availability::none);
  EXPECT_TRUE(w.output().available);
}

TEST(LdwWarning, ALaneFoundWithTheWheelNearTheLineIsNotWarnedUntilSeenInside) {
  LdwWarning w;
  double t = 0.0;
  hold(w, t, 0.9);
  LdwInput lost = input(t, 0.39, 0.5);
  lost.lane_tracked = false;
  w.update(lost);
  t += kDt;
  EXPECT_EQ(drift(w, t, 0.38, -0.3, 0.5).warnings, 0);
  // Likewise right after a lane change.
  LdwWarning w2;
  t = 0.0;
  hold(w2, t, 0.9);
  LdwInput changed = input(t, 0.35, 0.5);
  changed.lane_changed = true;
  w2.update(changed);
  t += kDt;
  EXPECT_EQ(drift(w2, t, 0.34, -0.3, 0.5).warnings, 0);
}

TEST(LdwWarning, NamesTheDisplayedValues) {
  EXPECT_STREQ(to_string(Side::none), "none");
  EXPECT_STREQ(to_string(Side::left), "left");
  EXPECT_STREQ(to_string(Side::right), "right");
  EXPECT_STREQ(to_string(Availability::none), "none");
  EXPECT_STREQ(to_string(Availability::too_slow), "too_slow");
  EXPECT_STREQ(to_string(Availability::no_lane), "no_lane");
  EXPECT_STREQ(to_string(Availability::not_calibrated), "not_calibrated");
  EXPECT_STREQ(to_string(Availability::camera_fault), "camera_fault");
  EXPECT_STREQ(to_string(Availability::gyro_fault), "gyro_fault");
  EXPECT_STREQ(to_string(Availability::vehicle_fault), "vehicle_fault");
  for (const TurnIndicator t : {TurnIndicator::none, TurnIndicator::left, TurnIndicator::right, TurnIndicator::both})
    EXPECT_EQ(turn_indicator_from_string(to_string(t)), t);
  EXPECT_FALSE(turn_indicator_from_string("hazard"));
  EXPECT_FALSE(turn_indicator_from_string(""));
}

}  // namespace
}  // namespace ccdlane::ldw
