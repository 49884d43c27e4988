// Quantiles of the chi-square distribution, for Mahalanobis gates and NEES bands.
#pragma once

namespace ccdlane::ldw {

// The p-quantile of chi-square with `dof` degrees of freedom (dof >= 1, 0 < p < 1):
// exact for 1 and 2 degrees of freedom (a squared normal; an exponential), beyond by the
// Wilson-Hilferty cube-root normal approximation, within 2 % at p = 0.999 for 3 and
// closer as dof grows (tested against tables).
double chi_square_quantile(int dof, double p);

// The p-quantile of the standard normal distribution (Acklam's rational approximation,
// relative error below 1.2e-9).
double normal_quantile(double p);

}  // namespace ccdlane::ldw
