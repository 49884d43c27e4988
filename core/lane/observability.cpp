// The checks run in this order so that the first problem named is the one to fix first:
// scale and focal length cannot be mended by any gyro, roll can.
#include "core/lane/observability.hpp"

namespace ccdlane {

Observability observability(const LaneEstimatorOptions& options, bool roll_measured) {
  const FreeSet& free = options.solver.free;
  const SolverPriors& p = options.priors;
  if (free.has(FreeParam::H) && !p.H_mm) return Observability::height_unobservable;
  if (free.has(FreeParam::f) && !p.f_mm) return Observability::focal_unobservable;
  if (roll_measured || !free.has(FreeParam::phi) || !free.has(FreeParam::y0) || p.phi_deg || p.lane_width_mm)
    return Observability::observable;
  return Observability::roll_unobservable;
}

bool roll_needs_gyro(const LaneEstimatorOptions& options) {
  return observability(options, false) == Observability::roll_unobservable;
}

const char* explain(Observability o) {
  switch (o) {
    case Observability::observable: return "";
    case Observability::height_unobservable:
      return "solver.free: H is free without [prior] H_mm: the camera height is not observable (scale); fix it or add "
             "the prior";
    case Observability::focal_unobservable:
      return "solver.free: f is free without [prior] f_mm: the focal length is not observable from one image; fix it "
             "or add the prior";
    case Observability::roll_unobservable:
      return "solver.free: phi and y0 are free with no gyro ([gyro] device), no [prior] phi_deg and no [prior] "
             "lane_width_mm: the roll is not observable; add one of them or fix phi";
  }
  return "";
}

}  // namespace ccdlane
