// Names of the per-frame result's enumerations, as docs/interfaces.md spells them.
#include "core/lane/lane_estimate.hpp"

namespace ccdlane {

const char* to_string(Departure d) {
  switch (d) {
    case Departure::none: return "none";
    case Departure::left: return "left";
    case Departure::right: return "right";
  }
  return "none";
}

const char* to_string(EstimatorState s) { return s == EstimatorState::tracking ? "tracking" : "searching"; }

const char* to_string(EstimateFailure f) {
  switch (f) {
    case EstimateFailure::none: return "none";
    case EstimateFailure::no_frame: return "no_frame";
    case EstimateFailure::too_few_marks: return "too_few_marks";
    case EstimateFailure::no_lane: return "no_lane";
    case EstimateFailure::solver_failed: return "solver_failed";
    case EstimateFailure::rank_deficient: return "rank_deficient";
  }
  return "none";
}

}  // namespace ccdlane
