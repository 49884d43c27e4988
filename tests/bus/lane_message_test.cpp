// LaneEstimate -> lane_estimate_t -> bytes -> lane_estimate_t -> LaneEstimate keeps
// every field; out-of-range values from a foreign publisher are clamped.
#include "bus/lane_message.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

LaneEstimate sample_estimate() {
  LaneEstimate e;
  e.frame = 123456789012ULL;
  e.t_ns = 987654321098765;
  e.ok = true;
  e.psi_deg = 1.05;
  e.theta_deg = 0.71;
  e.phi_deg = -2.7;
  e.sigma_psi_deg = 0.04;
  e.sigma_theta_deg = 0.03;
  e.sigma_phi_deg = kUndetermined;
  e.num_lines = 3;
  for (int i = 0; i < 3; ++i) {
    EstimatedLine& l = e.lines[static_cast<std::size_t>(i)];
    l.id = 10 + i;
    l.y0_mm = 1750.0 - 3500.0 * i;
    l.m = 0.0012 * (i + 1);
    l.c_per_mm = 1e-7 * i;
    l.marks = 9 - i;
    l.confidence = 0.97 - 0.1 * i;
    l.sigma_y0_mm = i == 2 ? kUndetermined : 20.0 + i;
  }
  e.lane_width_mm = 3601.0;
  e.lateral_offset_mm = -49.0;
  e.heading_deg = 0.07;
  e.departure = Departure::right;
  e.rms_px = 0.5;
  e.iterations = 5;
  e.latency_us = 180;
  return e;
}

// Same value, NaN equal to NaN.
void expect_same(double a, double b, const char* what) {
  if (std::isnan(a)) {
    EXPECT_TRUE(std::isnan(b)) << what;
  } else {
    EXPECT_EQ(a, b) << what;
  }
}

void expect_equal(const LaneEstimate& a, const LaneEstimate& b) {
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(a.t_ns, b.t_ns);
  EXPECT_EQ(a.ok, b.ok);
  EXPECT_EQ(a.reason, b.reason);
  expect_same(a.psi_deg, b.psi_deg, "psi");
  expect_same(a.theta_deg, b.theta_deg, "theta");
  expect_same(a.phi_deg, b.phi_deg, "phi");
  expect_same(a.sigma_psi_deg, b.sigma_psi_deg, "sigma psi");
  expect_same(a.sigma_theta_deg, b.sigma_theta_deg, "sigma theta");
  expect_same(a.sigma_phi_deg, b.sigma_phi_deg, "sigma phi");
  ASSERT_EQ(a.num_lines, b.num_lines);
  for (int i = 0; i < a.num_lines; ++i) {
    const auto& x = a.lines[static_cast<std::size_t>(i)];
    const auto& y = b.lines[static_cast<std::size_t>(i)];
    EXPECT_EQ(x.id, y.id);
    expect_same(x.y0_mm, y.y0_mm, "y0");
    expect_same(x.m, y.m, "m");
    expect_same(x.c_per_mm, y.c_per_mm, "c");
    EXPECT_EQ(x.marks, y.marks);
    expect_same(x.confidence, y.confidence, "confidence");
    expect_same(x.sigma_y0_mm, y.sigma_y0_mm, "sigma y0");
  }
  expect_same(a.lane_width_mm, b.lane_width_mm, "width");
  expect_same(a.lateral_offset_mm, b.lateral_offset_mm, "offset");
  expect_same(a.heading_deg, b.heading_deg, "heading");
  EXPECT_EQ(a.departure, b.departure);
  expect_same(a.rms_px, b.rms_px, "rms");
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.latency_us, b.latency_us);
}

// GCC 12 inlines the generated decode here and then takes its msg_hash, always written by
// __int64_t_decode_array before use, for maybe-uninitialized (since the message has a string).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
lane_estimate_t through_bytes(const lane_estimate_t& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  lane_estimate_t back;
  EXPECT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return back;
}
#pragma GCC diagnostic pop

TEST(LaneMessage, RoundTripThroughTheWireFormatKeepsEveryField) {
  const LaneEstimate e = sample_estimate();
  lane_estimate_t m;
  to_message(e, 1700000000123456, 1700000000123999, m);
  const lane_estimate_t back = through_bytes(m);
  EXPECT_EQ(back.capture_utime, 1700000000123456);
  EXPECT_EQ(back.publish_utime, 1700000000123999);
  expect_equal(from_message(back), e);
}

TEST(LaneMessage, NotOkKeepsItsReason) {
  LaneEstimate e;
  e.frame = 7;
  e.ok = false;
  e.reason = EstimateFailure::too_few_marks;
  lane_estimate_t m;
  to_message(e, 1, 2, m);
  EXPECT_EQ(m.reason, lane_estimate_t::REASON_TOO_FEW_MARKS);
  EXPECT_EQ(m.num_lines, 0);
  expect_equal(from_message(through_bytes(m)), e);
}

TEST(LaneMessage, UnusedLineSlotsAreZeroSoEqualEstimatesEncodeEqually) {
  LaneEstimate e = sample_estimate();
  lane_estimate_t m;
  for (auto& l : m.lines) l.y0_mm = 42.0;  // garbage from an earlier, longer message
  to_message(e, 1, 2, m);
  for (int i = e.num_lines; i < kMaxLaneLines; ++i) {
    EXPECT_EQ(m.lines[i].y0_mm, 0.0);
    EXPECT_EQ(m.lines[i].id, 0);
  }
}

TEST(LaneMessage, ForeignOutOfRangeValuesAreClamped) {
  lane_estimate_t m;
  to_message(sample_estimate(), 1, 2, m);
  m.num_lines = 100;
  m.departure = 9;
  m.ok = 0;
  m.reason = 77;
  LaneEstimate e = from_message(m);
  EXPECT_EQ(e.num_lines, kMaxLaneLines);
  EXPECT_EQ(e.departure, Departure::none);
  EXPECT_EQ(e.reason, EstimateFailure::solver_failed);
  m.num_lines = -3;
  m.ok = 1;
  e = from_message(m);
  EXPECT_EQ(e.num_lines, 0);
  EXPECT_EQ(e.reason, EstimateFailure::none);
}

}  // namespace
}  // namespace ccdlane
