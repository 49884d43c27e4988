// LaneEstimate <-> ccdlane::lane_estimate_t: the per-frame result in its LCM form.
#pragma once

#include <cstdint>

#include <ccdlane/lane_estimate_t.hpp>

#include "core/lane/lane_estimate.hpp"

namespace ccdlane {

// Fills every field of `out` (unused line slots zeroed, so equal estimates encode to
// equal bytes). No allocation: the publisher reuses one message object.
void to_message(const LaneEstimate& estimate, std::int64_t capture_utime, std::int64_t publish_utime,
                lane_estimate_t& out);

// For subscribers. Values a valid publisher cannot send (num_lines outside 0..8, an
// unknown reason or departure code) are clamped to the nearest meaning: 0/8 lines,
// reason solver_failed for a not-ok message (none for an ok one), departure none.
LaneEstimate from_message(const lane_estimate_t& message);

}  // namespace ccdlane
