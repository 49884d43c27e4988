// The conversion keeps the LCM constants and the C++ enums in step at compile time, so
// a new reason or departure kind cannot be published under a wrong number.
#include "bus/lane_message.hpp"

#include <algorithm>

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
  const int n = std::clamp(e.num_lines, 0, kMaxLaneLines);
  out.num_lines = static_cast<std::int8_t>(n);
  for (int i = 0; i < kMaxLaneLines; ++i) {
    if (i < n) copy_line(e.lines[static_cast<std::size_t>(i)], out.lines[i]);
    else out.lines[i] = lane_line_t{};
  }
  out.lane_width_mm = e.lane_width_mm;
  out.lateral_offset_mm = e.lateral_offset_mm;
  out.heading_deg = e.heading_deg;
  out.departure = static_cast<std::int8_t>(e.departure);
  out.rms_px = e.rms_px;
  out.iterations = e.iterations;
  out.latency_us = e.latency_us;
  out.roll_unobservable = e.roll_unobservable ? 1 : 0;
  out.source_frame = static_cast<std::int64_t>(e.source_frame);
}

LaneEstimate from_message(const lane_estimate_t& m) {
  LaneEstimate e;
  e.frame = static_cast<std::uint64_t>(m.frame);
  e.t_ns = m.t_ns;
  e.ok = m.ok != 0;
  if (m.reason > M::REASON_NONE && m.reason < kReasonCount) e.reason = static_cast<EstimateFailure>(m.reason);
  else e.reason = e.ok ? EstimateFailure::none : EstimateFailure::solver_failed;
  e.psi_deg = m.psi_deg;
  e.theta_deg = m.theta_deg;
  e.phi_deg = m.phi_deg;
  e.sigma_psi_deg = m.sigma_psi_deg;
  e.sigma_theta_deg = m.sigma_theta_deg;
  e.sigma_phi_deg = m.sigma_phi_deg;
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
  e.roll_unobservable = m.roll_unobservable != 0;
  e.source_frame = static_cast<std::uint64_t>(m.source_frame);
  return e;
}

}  // namespace ccdlane
