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
    l.near_mm = 4100.0 + i;
    l.far_mm = 61000.0 - 1000.0 * i;
  }
  e.lane_width_mm = 3601.0;
  e.lateral_offset_mm = -49.0;
  e.heading_deg = 0.07;
  e.curvature_per_m = -1.0 / 800.0;  // bending right, R 800 m
  e.departure = Departure::right;
  e.rms_px = 0.5;
  e.iterations = 5;
  e.latency_us = 180;
  LdwEstimate& l = e.ldw;
  l.available = true;
  l.reason = ldw::Availability::none;
  l.warning = ldw::Side::right;
  l.fired = ldw::Side::right;
  l.warnings = 3;
  l.track = ldw::TrackStatus::coasting;
  l.tracked = true;
  l.dlc_left_mm = 1210.5;
  l.dlc_right_mm = 240.25;
  l.tlc_right_s = 0.48;  // tlc_left_s empty: not approaching
  l.lateral_velocity_mps = -0.5;
  l.sigma_lateral_velocity_mps = 0.02;
  l.speed_mps = 20.0;
  l.indicator = TurnIndicator::both;
  l.offset_mm = -420.0;
  l.heading_deg = -1.4;
  l.curvature_per_m = 2e-3;
  l.lane_width_mm = 3750.0;
  l.pitch_deg = 3.1;
  l.roll_deg = 0.2;
  l.sigma_offset_mm = 20.0;
  l.sigma_heading_deg = 0.05;
  l.sigma_curvature_per_m = 1e-4;
  l.sigma_lane_width_mm = 15.0;
  l.sigma_pitch_deg = 0.04;
  l.sigma_roll_deg = kUndetermined;
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
    expect_same(x.near_mm, y.near_mm, "near");
    expect_same(x.far_mm, y.far_mm, "far");
  }
  expect_same(a.lane_width_mm, b.lane_width_mm, "width");
  expect_same(a.lateral_offset_mm, b.lateral_offset_mm, "offset");
  expect_same(a.heading_deg, b.heading_deg, "heading");
  expect_same(a.curvature_per_m, b.curvature_per_m, "curvature");
  EXPECT_EQ(a.departure, b.departure);
  expect_same(a.rms_px, b.rms_px, "rms");
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.latency_us, b.latency_us);
  const LdwEstimate &p = a.ldw, &q = b.ldw;
  EXPECT_EQ(p.available, q.available);
  EXPECT_EQ(p.reason, q.reason);
  EXPECT_EQ(p.warning, q.warning);
  EXPECT_EQ(p.fired, q.fired);
  EXPECT_EQ(p.warnings, q.warnings);
  EXPECT_EQ(p.track, q.track);
  EXPECT_EQ(p.tracked, q.tracked);
  expect_same(p.dlc_left_mm, q.dlc_left_mm, "dlc left");
  expect_same(p.dlc_right_mm, q.dlc_right_mm, "dlc right");
  EXPECT_EQ(p.tlc_left_s, q.tlc_left_s);
  EXPECT_EQ(p.tlc_right_s, q.tlc_right_s);
  const std::pair<double, double> same[] = {{p.lateral_velocity_mps, q.lateral_velocity_mps},
                                            {p.sigma_lateral_velocity_mps, q.sigma_lateral_velocity_mps},
                                            {p.speed_mps, q.speed_mps},
                                            {p.offset_mm, q.offset_mm},
                                            {p.heading_deg, q.heading_deg},
                                            {p.curvature_per_m, q.curvature_per_m},
                                            {p.lane_width_mm, q.lane_width_mm},
                                            {p.pitch_deg, q.pitch_deg},
                                            {p.roll_deg, q.roll_deg},
                                            {p.sigma_offset_mm, q.sigma_offset_mm},
                                            {p.sigma_heading_deg, q.sigma_heading_deg},
                                            {p.sigma_curvature_per_m, q.sigma_curvature_per_m},
                                            {p.sigma_lane_width_mm, q.sigma_lane_width_mm},
                                            {p.sigma_pitch_deg, q.sigma_pitch_deg},
                                            {p.sigma_roll_deg, q.sigma_roll_deg}};
  for (const auto& [x, y] : same) expect_same(x, y, "ldw state");
  EXPECT_EQ(p.indicator, q.indicator);
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

TEST(LaneMessage, LdwWithoutATrackSendsNaNDistances) {
  LaneEstimate e = sample_estimate();
  e.ldw.available = false;
  e.ldw.reason = ldw::Availability::too_slow;
  e.ldw.track = ldw::TrackStatus::lost;
  e.ldw.tracked = false;
  e.ldw.tlc_right_s.reset();
  lane_estimate_t m;
  to_message(e, 0, 0, m);
  EXPECT_TRUE(std::isnan(m.dlc_left_mm)) << "a consumer that ignores ldw_track must not read a distance";
  EXPECT_TRUE(std::isnan(m.dlc_right_mm));
  EXPECT_TRUE(std::isnan(m.tlc_right_s));
  EXPECT_EQ(m.ldw_reason, lane_estimate_t::LDW_REASON_TOO_SLOW);
  const LaneEstimate back = from_message(through_bytes(m));
  EXPECT_FALSE(back.ldw.tracked);
  EXPECT_EQ(back.ldw.reason, ldw::Availability::too_slow);
  EXPECT_FALSE(back.ldw.tlc_right_s);
}

TEST(LaneMessage, AVehicleFaultSurvivesTheBus) {
  LaneEstimate e = sample_estimate();
  e.ldw.available = false;
  e.ldw.reason = ldw::Availability::vehicle_fault;
  lane_estimate_t m;
  to_message(e, 0, 0, m);
  EXPECT_EQ(m.ldw_reason, lane_estimate_t::LDW_REASON_VEHICLE_FAULT);
  EXPECT_EQ(from_message(through_bytes(m)).ldw.reason, ldw::Availability::vehicle_fault);
}

TEST(LaneMessage, CurvatureAndRadiusOfTheLane) {
  LaneEstimate e = sample_estimate();
  lane_estimate_t m;
  to_message(e, 1, 2, m);
  EXPECT_EQ(m.curvature_per_m, -1.0 / 800.0);
  EXPECT_DOUBLE_EQ(m.radius_of_curvature_m, -800.0);
  e.curvature_per_m = 0.0;  // the straight model
  to_message(e, 1, 2, m);
  EXPECT_EQ(m.curvature_per_m, 0.0);
  EXPECT_TRUE(std::isinf(m.radius_of_curvature_m) && m.radius_of_curvature_m > 0);
  e.ok = false;
  e.reason = EstimateFailure::too_few_marks;  // nothing solved
  to_message(e, 1, 2, m);
  EXPECT_TRUE(std::isnan(m.curvature_per_m));
  EXPECT_TRUE(std::isnan(m.radius_of_curvature_m));
  EXPECT_EQ(from_message(through_bytes(m)).curvature_per_m, 0.0);
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
