// The per-frame result of the pipeline (docs/interfaces.md "Per-frame result"): what replay
// prints as JSON Lines and the daemon publishes over LCM, field for field.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "core/lane/support_problem.hpp"
#include "core/ldw/ldw_monitor.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane {

enum class Departure : std::uint8_t { none, left, right };
const char* to_string(Departure d);  // "none", "left", "right"

// Why a frame gave no usable estimate (ok = false).
enum class EstimateFailure : std::uint8_t {
  none,
  no_frame,        // the frame could not be read (replay) or was damaged
  too_few_marks,   // detection found fewer picks than the problem needs
  no_lane,         // no line on one side of the vehicle, or lines without a real lane's support
                   // (lane_support.hpp): no lane to be in
  solver_failed,   // the solver stopped without converging or rejected its input
  rank_deficient,  // the picks do not determine the free parameters
};
const char* to_string(EstimateFailure f);

// Where the estimator stands: searching (no previous frame to go on: the pose comes from
// the picture's vanishing point, else the mount) or tracking (the previous frame's pose
// and lines carried over).
enum class EstimatorState : std::uint8_t { searching, tracking };
const char* to_string(EstimatorState s);  // "searching", "tracking"

struct EstimatedLine {
  int id = 0;  // stable while the line stays in view
  double y0_mm = 0.0;
  double m = 0.0;
  double c_per_mm = 0.0;
  int marks = 0;            // picks on this line
  double confidence = 0.0;  // 0..1
  double sigma_y0_mm = kUndetermined;
  // Where this frame's picks on the line lie, road x ahead (mm), an isolated end mark left
  // out (lane_support.hpp's LineSupport): the stretch the line is seen over, its view range.
  // Beyond it the line is the model's extrapolation. 0, 0 without picks.
  double near_mm = 0.0, far_mm = 0.0;
};

// The lane departure warning at this frame: the LDW monitor's result, as it made it.
using LdwEstimate = ldw::LdwEstimate;

struct LaneEstimate {
  std::uint64_t frame = 0;  // source sequence number (replay: 0-based row of frames.csv)
  std::int64_t t_ns = 0;    // the frame's timestamp
  bool ok = false;
  EstimateFailure reason = EstimateFailure::none;
  EstimatorState state = EstimatorState::searching;
  // Why the lines found are not a lane (reason no_lane with lines on both sides).
  SupportProblem support = SupportProblem::none;
  double psi_deg = 0.0, theta_deg = 0.0, phi_deg = 0.0;
  double sigma_psi_deg = kUndetermined, sigma_theta_deg = kUndetermined, sigma_phi_deg = kUndetermined;
  // The camera's height above the road the lines and every distance are at: the mount's,
  // or what a cold start took from the lane-width prior (set whenever lines were solved).
  double H_mm = 0.0;
  int num_lines = 0;  // ordered left to right as seen from the vehicle (largest y0 first)
  std::array<EstimatedLine, kMaxLaneLines> lines{};
  double lane_width_mm = 0.0;
  double lateral_offset_mm = 0.0;  // positive: vehicle left of the lane centre
  double heading_deg = 0.0;        // positive: vehicle turned left of the lane
  // The lane's curvature at the vehicle from this frame's solve, 1/m, positive bending
  // left (lane_metrics.hpp); its radius is 1 / curvature. Set whenever lines were solved.
  double curvature_per_m = 0.0;
  Departure departure = Departure::none;
  double rms_px = 0.0;
  int iterations = 0;
  std::int64_t latency_us = 0;  // frame timestamp (or processing start) to result
  LdwEstimate ldw{};
  // No gyro reading for this frame while the configuration needs one to observe the roll
  // (phi and y0 free, no roll or lane-width prior): phi and y0 are not to be trusted.
  bool roll_unobservable = false;
  // The source's own id for the frame (Aravis block id, V4L2 sequence, frames.csv row),
  // which may wrap or restart; `frame` is the daemon's own count, unique within a run.
  std::uint64_t source_frame = 0;
};

}  // namespace ccdlane
