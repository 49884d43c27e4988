// The per-frame result as JSON, field for field as docs/interfaces.md lists it (`ccdlane
// replay` writes it, `ccdlane monitor` prints the same fields).
#pragma once

#include "core/lane/lane_estimate.hpp"
#include "tools/ccdlane/json_output.hpp"

namespace ccdlane::cli {

// {"frame", "t_ns", "ok", ["reason",] "psi_deg", "theta_deg", "phi_deg", "lines": [{"id",
// "y0_mm", "m", "c_per_mm", "marks", "confidence"}], "lane_width_mm",
// "lateral_offset_mm", "heading_deg", "departure", "rms_px", "iterations", "latency_us"}.
// "reason" is present only when ok is false. Values a failed frame does not have are
// null: the attitude and lines when nothing was solved, the lane quantities when there
// is no lane. With `sigmas`, a "sigma" object adds the solver's standard deviations
// (psi_deg, theta_deg, phi_deg, y0_mm per line; null where undetermined).
Json lane_estimate_json(const LaneEstimate& e, bool sigmas = false);

}  // namespace ccdlane::cli
