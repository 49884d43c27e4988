// The damping of a Levenberg-Marquardt loop and Nielsen's update of it from the gain
// ratio (Madsen, Nielsen & Tingleff, "Methods for non-linear least squares problems",
// 2004, eq. 3.16), shared by the lane solver's loop and camera calibration's
// (docs/solver.md "One damping rule, two loops").
#pragma once

#include <algorithm>

namespace ccdlane::solver {

struct NielsenDamping {
  double lambda = 1e-3;
  double nu = 2.0;

  // A step that decreased the cost, with gain ratio rho > 0 (actual over predicted
  // decrease): less damping the better the model predicted it.
  void accept(double rho) {
    const double t = 2.0 * rho - 1.0;
    lambda *= std::max(1.0 / 3.0, 1.0 - t * t * t);
    nu = 2.0;
  }
  // A step refused (no decrease, or no number): damp more, faster each time in a row.
  void reject() {
    lambda *= nu;
    nu *= 2.0;
  }
};

}  // namespace ccdlane::solver
