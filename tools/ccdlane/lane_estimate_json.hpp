// The per-frame result as JSON, field for field as docs/interfaces.md lists it (`ccdlane
// replay` writes it, `ccdlane monitor` prints the same fields).
#pragma once

#include "core/lane/lane_estimate.hpp"
#include "tools/ccdlane/json_output.hpp"

namespace ccdlane::cli {

// {"frame", "t_ns", "ok", ["reason",] "psi_deg", "theta_deg", "phi_deg", "H_mm", "lines": [{"id",
// "y0_mm", "m", "c_per_mm", "marks", "confidence", "near_mm", "far_mm"}], "lane_width_mm",
// "lateral_offset_mm", "heading_deg", "curvature_per_m", "radius_of_curvature_m",
// "departure", "rms_px", "iterations", "latency_us"}. The radius is null on a straight
// lane (curvature exactly 0, as the straight line model always gives).
// "reason" is present only when ok is false. Values a failed frame does not have are
// null: the attitude and lines when nothing was solved, the lane quantities when there
// is no lane. With `sigmas`, a "sigma" object adds the solver's standard deviations
// (psi_deg, theta_deg, phi_deg, y0_mm per line; null where undetermined).
// Always with an "ldw" object (ldw_json).
Json lane_estimate_json(const LaneEstimate& e, bool sigmas = false);

// The lane departure warning (interfaces.md "Per-frame result", ldw): {"available",
// "reason" ("none" when available), "warning" and "fired" ("none"/"left"/"right"),
// "warnings", "dlc_left_mm", "dlc_right_mm", "tlc_left_s", "tlc_right_s",
// "lateral_velocity_mps" (+ toward the left), "speed_mps", "turn_indicator", "track",
// "state": {"offset_mm", "heading_deg", "curvature_per_m", "lane_width_mm", "pitch_deg",
// "roll_deg"}, "sigma": {the same and "lateral_velocity_mps"}}. DLC, lateral velocity
// and the state are null while the lane filter has no track; a TLC is null while that
// wheel is not approaching its line; a sigma is null where not estimated (roll with a
// gyro).
Json ldw_json(const LdwEstimate& ldw);

}  // namespace ccdlane::cli
