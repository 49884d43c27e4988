// Central finite differences for checking the solver's analytic Jacobians.
#pragma once

#include <functional>

#include <Eigen/Core>

namespace ccdlane::test {

// d f / d t at t = 0 for a vector-valued f, by central differences with step h.
inline Eigen::VectorXd central_difference(const std::function<Eigen::VectorXd(double)>& f, double h) {
  return (f(h) - f(-h)) / (2.0 * h);
}

}  // namespace ccdlane::test
