// The conversion keeps the LCM constants and the C++ enums in step at compile time, so
// a new reason or departure kind cannot be published under a wrong number.
#include "bus/lane_message.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ccdlane {
namespace {

using M = lane_estimate_t;
static_assert(M::MAX_LINES == kMaxLaneLines, "lane_estimate_t.lcm lines[] must hold kMaxLaneLines");
static_assert(sizeof(M::lines) / sizeof(M::lines[0]) == kMaxLaneLines);
static_assert(M::REASON_NONE == static_cast<int>(EstimateFailure::none));
static_assert(M::REASON_NO_FRAME == static_cast<int>(EstimateFailure::no_frame));
static_assert(M::REASON_TOO_FEW_MARKS == static_cast<int>(EstimateFailure::too_few_marks));
static_assert(M::REASON_NO_LANE == static_cast<int>(EstimateFailure::no_lane));
static_assert(M::REASON_SOLVER_FAILED == static_cast<int>(EstimateFailure::solver_failed));
static_assert(M::REASON_RANK_DEFICIENT == static_cast<int>(EstimateFailure::rank_deficient));
static_assert(M::DEPARTURE_NONE == static_cast<int>(Departure::none));
static_assert(M::DEPARTURE_LEFT == static_cast<int>(Departure::left));
static_assert(M::DEPARTURE_RIGHT == static_cast<int>(Departure::right));
constexpr int kReasonCount = M::REASON_RANK_DEFICIENT + 1;
static_assert(M::LDW_REASON_NONE == static_cast<int>(ldw::Availability::none));
static_assert(M::LDW_REASON_CAMERA_FAULT == static_cast<int>(ldw::Availability::camera_fault));
static_assert(M::LDW_REASON_GYRO_FAULT == static_cast<int>(ldw::Availability::gyro_fault));
static_assert(M::LDW_REASON_NOT_CALIBRATED == static_cast<int>(ldw::Availability::not_calibrated));
static_assert(M::LDW_REASON_NO_LANE == static_cast<int>(ldw::Availability::no_lane));
static_assert(M::LDW_REASON_TOO_SLOW == static_cast<int>(ldw::Availability::too_slow));
static_assert(M::LDW_REASON_VEHICLE_FAULT == static_cast<int>(ldw::Availability::vehicle_fault));
static_assert(M::WARNING_NONE == static_cast<int>(ldw::Side::none));
static_assert(M::WARNING_LEFT == static_cast<int>(ldw::Side::left));
static_assert(M::WARNING_RIGHT == static_cast<int>(ldw::Side::right));
static_assert(M::TRACK_LOST == static_cast<int>(ldw::TrackStatus::lost));
static_assert(M::TRACK_TENTATIVE == static_cast<int>(ldw::TrackStatus::tentative));
static_assert(M::TRACK_TRACKING == static_cast<int>(ldw::TrackStatus::tracking));
static_assert(M::TRACK_COASTING == static_cast<int>(ldw::TrackStatus::coasting));
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ldw::Side side_from_code(std::int8_t code) {
  return code >= M::WARNING_NONE && code <= M::WARNING_RIGHT ? static_cast<ldw::Side>(code) : ldw::Side::none;
}

void to_ldw_fields(const LdwEstimate& l, lane_estimate_t& out) {
  out.ldw_available = l.available ? 1 : 0;
  out.ldw_reason = static_cast<std::int8_t>(l.reason);
  out.ldw_warning = static_cast<std::int8_t>(l.warning);
  out.ldw_fired = static_cast<std::int8_t>(l.fired);
  out.ldw_warnings = static_cast<std::int32_t>(l.warnings);
  out.ldw_track = static_cast<std::int8_t>(l.track);
  out.dlc_left_mm = l.tracked ? l.dlc_left_mm : kNaN;
  out.dlc_right_mm = l.tracked ? l.dlc_right_mm : kNaN;
  out.tlc_left_s = l.tlc_left_s.value_or(kNaN);
  out.tlc_right_s = l.tlc_right_s.value_or(kNaN);
  out.lateral_velocity_mps = l.lateral_velocity_mps;
  out.sigma_lateral_velocity_mps = l.sigma_lateral_velocity_mps;
  out.speed_mps = l.speed_mps;
  out.turn_indicator = static_cast<std::int8_t>(l.indicator);
  out.filtered_offset_mm = l.offset_mm;
  out.filtered_heading_deg = l.heading_deg;
  out.filtered_curvature_per_m = l.curvature_per_m;
  out.filtered_lane_width_mm = l.lane_width_mm;
  out.filtered_pitch_deg = l.pitch_deg;
  out.filtered_roll_deg = l.roll_deg;
  out.sigma_filtered_offset_mm = l.sigma_offset_mm;
  out.sigma_filtered_heading_deg = l.sigma_heading_deg;
  out.sigma_filtered_curvature_per_m = l.sigma_curvature_per_m;
  out.sigma_filtered_lane_width_mm = l.sigma_lane_width_mm;
  out.sigma_filtered_pitch_deg = l.sigma_pitch_deg;
  out.sigma_filtered_roll_deg = l.sigma_roll_deg;
  out.filtered_heading_bias_deg = l.heading_bias_deg;
  out.sigma_filtered_heading_bias_deg = l.sigma_heading_bias_deg;
}

LdwEstimate from_ldw_fields(const lane_estimate_t& m) {
  LdwEstimate l;
  l.available = m.ldw_available != 0;
  l.reason = m.ldw_reason >= M::LDW_REASON_NONE && m.ldw_reason <= M::LDW_REASON_VEHICLE_FAULT
                 ? static_cast<ldw::Availability>(m.ldw_reason)
                 : (l.available ? ldw::Availability::none : ldw::Availability::no_lane);
  l.warning = side_from_code(m.ldw_warning);
  l.fired = side_from_code(m.ldw_fired);
  l.warnings = static_cast<std::uint32_t>(std::max(0, m.ldw_warnings));
  l.track = m.ldw_track >= M::TRACK_LOST && m.ldw_track <= M::TRACK_COASTING
                ? static_cast<ldw::TrackStatus>(m.ldw_track)
                : ldw::TrackStatus::lost;
  l.tracked = l.track != ldw::TrackStatus::lost;
  l.dlc_left_mm = l.tracked ? m.dlc_left_mm : 0.0;
  l.dlc_right_mm = l.tracked ? m.dlc_right_mm : 0.0;
  if (std::isfinite(m.tlc_left_s)) l.tlc_left_s = m.tlc_left_s;
  if (std::isfinite(m.tlc_right_s)) l.tlc_right_s = m.tlc_right_s;
  l.lateral_velocity_mps = m.lateral_velocity_mps;
  l.sigma_lateral_velocity_mps = m.sigma_lateral_velocity_mps;
  l.speed_mps = m.speed_mps;
  l.indicator = m.turn_indicator >= 0 && m.turn_indicator <= static_cast<int>(TurnIndicator::both)
                    ? static_cast<TurnIndicator>(m.turn_indicator)
                    : TurnIndicator::none;
  l.offset_mm = m.filtered_offset_mm;
  l.heading_deg = m.filtered_heading_deg;
  l.curvature_per_m = m.filtered_curvature_per_m;
  l.lane_width_mm = m.filtered_lane_width_mm;
  l.pitch_deg = m.filtered_pitch_deg;
  l.roll_deg = m.filtered_roll_deg;
  l.sigma_offset_mm = m.sigma_filtered_offset_mm;
  l.sigma_heading_deg = m.sigma_filtered_heading_deg;
  l.sigma_curvature_per_m = m.sigma_filtered_curvature_per_m;
  l.sigma_lane_width_mm = m.sigma_filtered_lane_width_mm;
  l.sigma_pitch_deg = m.sigma_filtered_pitch_deg;
  l.sigma_roll_deg = m.sigma_filtered_roll_deg;
  l.heading_bias_deg = m.filtered_heading_bias_deg;
  l.sigma_heading_bias_deg = m.sigma_filtered_heading_bias_deg;
  return l;
}

// EstimatedLine and lane_line_t name their fields alike; one copy serves both ways.
template <typename From, typename To>
void copy_line(const From& from, To& to) {
  to.id = from.id;
  to.y0_mm = from.y0_mm;
  to.m = from.m;
  to.c_per_mm = from.c_per_mm;
  to.marks = from.marks;
  to.confidence = from.confidence;
  to.sigma_y0_mm = from.sigma_y0_mm;
  to.near_mm = from.near_mm;
  to.far_mm = from.far_mm;
}

}  // namespace

void to_message(const LaneEstimate& e, std::int64_t capture_utime, std::int64_t publish_utime, lane_estimate_t& out) {
  out.publish_utime = publish_utime;
  out.capture_utime = capture_utime;
  out.frame = static_cast<std::int64_t>(e.frame);
  out.t_ns = e.t_ns;
  out.ok = e.ok ? 1 : 0;
  out.reason = static_cast<std::int8_t>(e.reason);
  out.psi_deg = e.psi_deg;
  out.theta_deg = e.theta_deg;
  out.phi_deg = e.phi_deg;
  out.sigma_psi_deg = e.sigma_psi_deg;
  out.sigma_theta_deg = e.sigma_theta_deg;
  out.sigma_phi_deg = e.sigma_phi_deg;
  out.H_mm = e.H_mm;
  const int n = std::clamp(e.num_lines, 0, kMaxLaneLines);
  out.num_lines = static_cast<std::int8_t>(n);
  for (int i = 0; i < kMaxLaneLines; ++i) {
    if (i < n)
      copy_line(e.lines[static_cast<std::size_t>(i)], out.lines[i]);
    else
      out.lines[i] = lane_line_t{};
  }
  out.lane_width_mm = e.lane_width_mm;
  out.lateral_offset_mm = e.lateral_offset_mm;
  out.heading_deg = e.heading_deg;
  out.departure = static_cast<std::int8_t>(e.departure);
  out.rms_px = e.rms_px;
  out.iterations = e.iterations;
  out.latency_us = e.latency_us;
  to_ldw_fields(e.ldw, out);
  out.roll_unobservable = e.roll_unobservable ? 1 : 0;
  out.source_frame = static_cast<std::int64_t>(e.source_frame);
  out.state = e.state == EstimatorState::tracking ? M::STATE_TRACKING : M::STATE_SEARCHING;
  // Lines were solved on ok frames and on those that failed only after the solve.
  const bool solved = e.ok || e.reason == EstimateFailure::no_lane || e.reason == EstimateFailure::rank_deficient;
  out.curvature_per_m = solved ? e.curvature_per_m : kNaN;
  out.radius_of_curvature_m = !solved                    ? kNaN
                              : e.curvature_per_m != 0.0 ? 1.0 / e.curvature_per_m
                                                         : std::numeric_limits<double>::infinity();
}

LaneEstimate from_message(const lane_estimate_t& m) {
  LaneEstimate e;
  e.frame = static_cast<std::uint64_t>(m.frame);
  e.t_ns = m.t_ns;
  e.ok = m.ok != 0;
  if (m.reason > M::REASON_NONE && m.reason < kReasonCount)
    e.reason = static_cast<EstimateFailure>(m.reason);
  else
    e.reason = e.ok ? EstimateFailure::none : EstimateFailure::solver_failed;
  e.psi_deg = m.psi_deg;
  e.theta_deg = m.theta_deg;
  e.phi_deg = m.phi_deg;
  e.sigma_psi_deg = m.sigma_psi_deg;
  e.sigma_theta_deg = m.sigma_theta_deg;
  e.sigma_phi_deg = m.sigma_phi_deg;
  e.H_mm = m.H_mm;
  e.num_lines = std::clamp(static_cast<int>(m.num_lines), 0, kMaxLaneLines);
  for (int i = 0; i < e.num_lines; ++i) copy_line(m.lines[i], e.lines[static_cast<std::size_t>(i)]);
  e.lane_width_mm = m.lane_width_mm;
  e.lateral_offset_mm = m.lateral_offset_mm;
  e.heading_deg = m.heading_deg;
  e.departure = (m.departure >= M::DEPARTURE_NONE && m.departure <= M::DEPARTURE_RIGHT)
                    ? static_cast<Departure>(m.departure)
                    : Departure::none;
  e.rms_px = m.rms_px;
  e.iterations = m.iterations;
  e.latency_us = m.latency_us;
  e.ldw = from_ldw_fields(m);
  e.roll_unobservable = m.roll_unobservable != 0;
  e.source_frame = static_cast<std::uint64_t>(m.source_frame);
  e.state = m.state == M::STATE_TRACKING ? EstimatorState::tracking : EstimatorState::searching;
  e.curvature_per_m = std::isfinite(m.curvature_per_m) ? m.curvature_per_m : 0.0;
  return e;
}

}  // namespace ccdlane
