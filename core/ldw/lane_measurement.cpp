// The solve's free parameters mapped to the filter's measurement by the Jacobian of the
// mapping: value z(p), covariance J Sigma J^T over the solver's reduced parameters.
#include "core/ldw/lane_measurement.hpp"

#include <cmath>

namespace ccdlane::ldw {

LaneMeasurement measurement_from_solve(const SolveResult& r, int left_line, int right_line, double mount_psi_rad,
                                       bool roll_is_measured) {
  LaneMeasurement m;
  const RoadLine& L = r.lines[static_cast<std::size_t>(left_line)];
  const RoadLine& R = r.lines[static_cast<std::size_t>(right_line)];
  const double mean_slope = 0.5 * (L.m + R.m);
  m.value << L.y0_mm * 1e-3, R.y0_mm * 1e-3, r.pose.attitude.psi - mount_psi_rad - std::atan(mean_slope),
      (L.c_per_mm + R.c_per_mm) * 1e3, r.pose.attitude.theta, r.pose.attitude.phi;

  // d(measurement)/d(reduced parameter), and which components the free set reaches.
  const int n = r.num_free;
  Eigen::Matrix<double, kMeasurementSize, Eigen::Dynamic, 0, kMeasurementSize, kMaxReducedParams> J(kMeasurementSize,
                                                                                                    n);
  J.setZero();
  std::array<int, kMeasurementSize> reached{};  // free parameters feeding each component
  const double d_atan = 1.0 / (1.0 + mean_slope * mean_slope);
  for (int j = 0; j < n; ++j) {
    const ReducedParam& p = r.free_params[static_cast<std::size_t>(j)];
    const bool own = p.line == left_line || p.line == right_line;
    auto set = [&](int row, double d) {
      J(row, j) = d;
      ++reached[static_cast<std::size_t>(row)];
    };
    switch (p.kind) {
      case FreeParam::psi: set(kMeasuredHeading, 1.0); break;
      case FreeParam::theta: set(kMeasuredPitch, 1.0); break;
      case FreeParam::phi: set(kMeasuredRoll, 1.0); break;
      case FreeParam::y0:
        if (p.line == left_line) set(kLeftLine, 1e-3);
        if (p.line == right_line) set(kRightLine, 1e-3);
        break;
      case FreeParam::m:
        if (own) set(kMeasuredHeading, -0.5 * d_atan);
        break;
      case FreeParam::c:
        if (own) set(kMeasuredCurvature, 1e3);
        break;
      case FreeParam::H:
      case FreeParam::f: break;
    }
  }
  // Undetermined parameters (NaN rows): zero here, and what depends on them is absent
  // (0 * NaN would spoil every component).
  ReducedMatrix sigma = r.covariance.topLeftCorner(n, n);
  std::array<bool, kMeasurementSize> undetermined{};
  for (int j = 0; j < n; ++j) {
    if (std::isfinite(sigma(j, j))) continue;
    sigma.row(j).setZero();
    sigma.col(j).setZero();
    for (int i = 0; i < kMeasurementSize; ++i) undetermined[static_cast<std::size_t>(i)] |= J(i, j) != 0.0;
  }
  m.covariance = J * sigma * J.transpose();
  for (int i = 0; i < kMeasurementSize; ++i)
    m.present[static_cast<std::size_t>(i)] = reached[static_cast<std::size_t>(i)] > 0 &&
                                             !undetermined[static_cast<std::size_t>(i)] && std::isfinite(m.value(i));
  // Curvature needs both lines' c; a lone line's would be half of it.
  if (reached[kMeasuredCurvature] < 2) m.present[kMeasuredCurvature] = false;
  if (!roll_is_measured) m.present[kMeasuredRoll] = false;
  // Absent rows and columns: zero, with a unit diagonal, so nothing NaN is left around.
  for (int i = 0; i < kMeasurementSize; ++i) {
    if (m.present[static_cast<std::size_t>(i)]) continue;
    m.covariance.row(i).setZero();
    m.covariance.col(i).setZero();
    m.covariance(i, i) = 1.0;
  }
  return m;
}

}  // namespace ccdlane::ldw
