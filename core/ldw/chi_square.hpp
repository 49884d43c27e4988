// Quantiles of the chi-square distribution, for Mahalanobis gates and NEES bands.
#pragma once

namespace ccdlane::ldw {

// The p-quantile of chi-square with `dof` degrees of freedom (dof >= 1, 0 < p < 1), by
// the Wilson-Hilferty cube-root normal approximation: within 3 % of the exact value
// for dof = 1 at p = 0.999 and closer as dof grows (tested against tables).
double chi_square_quantile(int dof, double p);

// The p-quantile of the standard normal distribution (Acklam's rational approximation,
// relative error below 1.2e-9).
double normal_quantile(double p);

}  // namespace ccdlane::ldw
